// An open HDF5 group (or file root) that knows its file path and its own
// path inside the file, so every error names both:
//   "run/sample.h5: /particles/radius: missing".
//
// Datasets are written with little-endian IEEE/integer file types and read
// into native memory types (no conversion on x86: doubles round-trip bit for
// bit). Every dataset written here carries a `units` string attribute
// ("1" for dimensionless). Arrays are 1-D (cols == 0) or 2-D row-major
// (rows x cols); scalars use a scalar dataspace. Strings are UTF-8
// variable-length (h5py reads them as str); fixed-length strings are accepted
// on reading.
//
// Every call silences HDF5's error printing for its duration and throws
// std::runtime_error on failure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "virtual_triaxial/io/hdf5_handle.h"

namespace vt::io::h5 {

class Group {
 public:
  Group() = default;
  Group(Handle handle, std::string file, std::string path)
      : handle_(std::move(handle)), file_(std::move(file)), path_(std::move(path)) {}

  /// Root group of an existing file, opened read-only. Throws when the file
  /// is missing or not HDF5.
  static Group open_file_read(const std::string& file);

  hid_t id() const { return handle_.get(); }
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  /// Path of a child: "/particles" + "radius" -> "/particles/radius".
  std::string child_path(const std::string& name) const;
  /// "file: /path/name"
  std::string where(const std::string& name) const;
  [[noreturn]] void fail(const std::string& name, const std::string& reason) const;
  void close() { handle_.reset(); }

  bool has(const std::string& name) const;
  Group create_group(const std::string& name) const;
  Group open_group(const std::string& name) const;
  /// Names of the links in this group (sorted by name).
  std::vector<std::string> children() const;

  // ---- datasets (T: double, int64, int32, uint64, uint8) --------------------
  template <class T>
  void write(const std::string& name, const std::vector<T>& data, std::size_t rows, std::size_t cols,
             const std::string& units) const;
  template <class T>
  void write_scalar(const std::string& name, T value, const std::string& units) const;
  /// Number of rows (first dimension) of a 1-D or 2-D dataset.
  std::size_t rows(const std::string& name) const;
  /// Read a rows x cols (cols == 0: 1-D of length rows) dataset; a shape
  /// mismatch is an error naming the dataset; `rows_from` says where the
  /// expected length came from (for the message).
  template <class T>
  std::vector<T> read(const std::string& name, std::size_t rows, std::size_t cols,
                      const std::string& rows_from = {}) const;
  template <class T>
  T read_scalar(const std::string& name) const;
  /// The `units` attribute of a dataset ("" if absent).
  std::string units(const std::string& name) const;

  // ---- attributes of this group -------------------------------------------
  bool has_attr(const std::string& name) const;
  std::vector<std::string> attr_names() const;
  void set_attr(const std::string& name, double value) const;
  void set_attr(const std::string& name, std::int64_t value) const;
  void set_attr(const std::string& name, const std::string& value) const;
  void set_attr(const std::string& name, const char* value) const { set_attr(name, std::string(value)); }
  double attr_double(const std::string& name) const;
  std::int64_t attr_int(const std::string& name) const;
  std::string attr_string(const std::string& name) const;
  /// True when the attribute holds a floating-point number.
  bool attr_is_float(const std::string& name) const;
  bool attr_is_string(const std::string& name) const;

 private:
  Handle handle_;
  std::string file_;
  std::string path_;
};

// Attribute helpers on any object (dataset or group), used by Group.
void write_string_attr(hid_t obj, const std::string& name, const std::string& value);
/// Reads a string attribute; returns false if absent; throws `what: reason`
/// if present but not a string.
bool read_string_attr(hid_t obj, const std::string& name, std::string& out, const std::string& what);

}  // namespace vt::io::h5
