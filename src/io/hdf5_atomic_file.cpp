#include "virtual_triaxial/io/hdf5_atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace vt::io::h5 {

namespace {

std::string directory_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

/// fsync a file or directory; returns errno (0 on success).
int sync_path(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) return errno;
  const int rc = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  return rc;
}

}  // namespace

AtomicFile::AtomicFile(const std::string& path)
    : path_(path), temp_(path + ".tmp." + std::to_string(::getpid())) {
  ErrorSilencer quiet;
  if (path.empty()) throw std::runtime_error("HDF5 output: empty file path");
  if (::access(directory_of(path).c_str(), W_OK) != 0) {
    const int err = errno;
    throw std::runtime_error(path + ": cannot write: directory '" + directory_of(path) + "': " + std::strerror(err));
  }
  // Semi close degree: closing the file fails if an object in it is still
  // open, so a forgotten handle is an error instead of a silently deferred
  // (and therefore non-atomic) close.
  Handle fapl = plist_handle(H5Pcreate(H5P_FILE_ACCESS));
  if (!fapl || H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_SEMI) < 0)
    throw std::runtime_error(with_reason(path + ": cannot set up file access properties"));
  // No modification times on the root group either: identical content gives
  // identical bytes.
  const hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (fcpl >= 0) H5Pset_obj_track_times(fcpl, false);
  file_ = file_handle(H5Fcreate(temp_.c_str(), H5F_ACC_TRUNC, fcpl >= 0 ? fcpl : H5P_DEFAULT, fapl.get()));
  if (fcpl >= 0) H5Pclose(fcpl);
  if (!file_) {
    std::remove(temp_.c_str());
    throw std::runtime_error(with_reason(path + ": cannot create temporary file '" + temp_ + "'"));
  }
  Handle root = group_handle(H5Gopen2(file_.get(), "/", H5P_DEFAULT));
  if (!root) {
    discard();
    throw std::runtime_error(with_reason(path + ": cannot open the root group"));
  }
  root_ = Group(std::move(root), path_, "/");
}

AtomicFile::~AtomicFile() {
  if (!committed_) discard();
}

void AtomicFile::discard() noexcept {
  ErrorSilencer quiet;
  root_.close();
  file_.reset();
  std::remove(temp_.c_str());
  H5Eclear2(H5E_DEFAULT);
}

void AtomicFile::commit() {
  ErrorSilencer quiet;
  if (committed_) return;
  root_.close();
  if (file_.close() < 0) {
    const std::string msg = with_reason(path_ + ": cannot close temporary file '" + temp_ + "'");
    discard();
    throw std::runtime_error(msg);
  }
  if (const int err = sync_path(temp_, false)) {
    discard();
    throw std::runtime_error(path_ + ": cannot sync temporary file '" + temp_ + "': " + std::strerror(err));
  }
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    const int err = errno;
    discard();
    throw std::runtime_error(path_ + ": cannot rename '" + temp_ + "' into place: " + std::strerror(err));
  }
  committed_ = true;
  // Make the rename itself durable; failure here leaves a complete file.
  (void)sync_path(directory_of(path_), true);
}

}  // namespace vt::io::h5
