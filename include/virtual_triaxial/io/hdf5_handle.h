// RAII ownership of HDF5 C-API identifiers (hid_t) and HDF5 error handling.
//
// Handle closes its identifier with the matching H5*close function when it
// goes out of scope, so no identifier leaks on an error path (an exception
// unwinds through the destructors). ErrorSilencer turns off HDF5's automatic
// printing of its error stack for the lifetime of the object (and restores
// the previous setting); error_reason() turns the current error stack into
// one line for an exception message.
//
// Not thread-safe: the Debian HDF5 build is not thread-safe, so HDF5 calls
// (and therefore these files) must not be used from several threads at once.
#pragma once

#include <hdf5.h>

#include <string>

namespace vt::io::h5 {

class Handle {
 public:
  using Closer = herr_t (*)(hid_t);

  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  ~Handle() { reset(); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      closer_ = o.closer_;
      o.id_ = H5I_INVALID_HID;
    }
    return *this;
  }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  explicit operator bool() const { return valid(); }
  /// Close (errors ignored); the handle becomes invalid.
  void reset() noexcept;
  /// Close and return the H5*close status (>= 0 on success, also when empty).
  herr_t close() noexcept;

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer closer_ = nullptr;
};

// Wrap a freshly returned identifier (which may be negative = failure).
inline Handle file_handle(hid_t id) { return Handle(id, &H5Fclose); }
inline Handle group_handle(hid_t id) { return Handle(id, &H5Gclose); }
inline Handle dataset_handle(hid_t id) { return Handle(id, &H5Dclose); }
inline Handle dataspace_handle(hid_t id) { return Handle(id, &H5Sclose); }
inline Handle datatype_handle(hid_t id) { return Handle(id, &H5Tclose); }
inline Handle attribute_handle(hid_t id) { return Handle(id, &H5Aclose); }
inline Handle plist_handle(hid_t id) { return Handle(id, &H5Pclose); }
inline Handle object_handle(hid_t id) { return Handle(id, &H5Oclose); }

/// Disables HDF5's automatic error-stack printing while alive.
class ErrorSilencer {
 public:
  ErrorSilencer();
  ~ErrorSilencer();
  ErrorSilencer(const ErrorSilencer&) = delete;
  ErrorSilencer& operator=(const ErrorSilencer&) = delete;

 private:
  H5E_auto2_t old_func_ = nullptr;
  void* old_data_ = nullptr;
  bool saved_ = false;
};

/// The most specific message on HDF5's default error stack (empty if none),
/// then clears the stack.
std::string error_reason();

/// "what" plus ": " + error_reason() when HDF5 recorded one.
std::string with_reason(const std::string& what);

}  // namespace vt::io::h5
