#include "virtual_triaxial/io/hdf5_handle.h"

namespace vt::io::h5 {

void Handle::reset() noexcept { (void)close(); }

herr_t Handle::close() noexcept {
  herr_t status = 0;
  if (id_ >= 0 && closer_ != nullptr) status = closer_(id_);
  id_ = H5I_INVALID_HID;
  return status;
}

ErrorSilencer::ErrorSilencer() {
  saved_ = H5Eget_auto2(H5E_DEFAULT, &old_func_, &old_data_) >= 0;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

ErrorSilencer::~ErrorSilencer() {
  if (saved_) H5Eset_auto2(H5E_DEFAULT, old_func_, old_data_);
}

namespace {

struct WalkData {
  std::string innermost;
  std::string errno_text;
};

herr_t walk_cb(unsigned n, const H5E_error2_t* err, void* client) {
  auto* data = static_cast<WalkData*>(client);
  if (n == 0 && err != nullptr && err->desc != nullptr) data->innermost = err->desc;
  return 0;
}

}  // namespace

std::string error_reason() {
  WalkData data;
  // Upward walk starts at the innermost (most specific) frame.
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, &walk_cb, &data);
  H5Eclear2(H5E_DEFAULT);
  return data.innermost;
}

std::string with_reason(const std::string& what) {
  const std::string reason = error_reason();
  return reason.empty() ? what : what + " (" + reason + ")";
}

}  // namespace vt::io::h5
