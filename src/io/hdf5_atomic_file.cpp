#include "virtual_triaxial/io/hdf5_atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

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

/// Writes all of `data` to a new file `path` and fsyncs it; "" or the reason.
std::string write_all(const std::string& path, const std::vector<unsigned char>& data) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return std::strerror(errno);
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : ENOSPC;
      ::close(fd);
      return std::strerror(err);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    return std::strerror(err);
  }
  if (::close(fd) != 0) return std::strerror(errno);
  return "";
}

}  // namespace

AtomicFile::AtomicFile(const std::string& path)
    : path_(path), temp_(path + ".tmp." + std::to_string(::getpid())) {
  ErrorSilencer quiet;
  if (path.empty()) throw WriteError("HDF5 output: empty file path");
  if (::access(directory_of(path).c_str(), W_OK) != 0) {
    const int err = errno;
    throw WriteError(path + ": cannot write: directory '" + directory_of(path) + "': " + std::strerror(err));
  }
  // Semi close degree: closing the file fails if an object in it is still
  // open, so a forgotten handle is an error instead of a silently deferred
  // close. Core driver without backing store: the file lives in memory.
  Handle fapl = plist_handle(H5Pcreate(H5P_FILE_ACCESS));
  if (!fapl || H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_SEMI) < 0 ||
      H5Pset_fapl_core(fapl.get(), std::size_t{1} << 20, false) < 0)
    throw std::runtime_error(with_reason(path + ": cannot set up file access properties"));
  // No modification times on the root group either: identical content gives
  // identical bytes.
  const hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (fcpl >= 0) H5Pset_obj_track_times(fcpl, false);
  file_ = file_handle(H5Fcreate(temp_.c_str(), H5F_ACC_TRUNC, fcpl >= 0 ? fcpl : H5P_DEFAULT, fapl.get()));
  if (fcpl >= 0) H5Pclose(fcpl);
  if (!file_) throw std::runtime_error(with_reason(path + ": cannot create the file in memory"));
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
  ::unlink(temp_.c_str());
  H5Eclear2(H5E_DEFAULT);
}

void AtomicFile::commit() {
  ErrorSilencer quiet;
  if (committed_) return;
  root_.close();
  if (H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) {
    const std::string msg = with_reason(path_ + ": cannot flush the file in memory");
    discard();
    throw std::runtime_error(msg);
  }
  const ssize_t size = H5Fget_file_image(file_.get(), nullptr, 0);
  std::vector<unsigned char> image(size > 0 ? static_cast<std::size_t>(size) : 0);
  if (size <= 0 || H5Fget_file_image(file_.get(), image.data(), image.size()) != size) {
    const std::string msg = with_reason(path_ + ": cannot take the file image");
    discard();
    throw std::runtime_error(msg);
  }
  if (file_.close() < 0) {
    const std::string msg = with_reason(path_ + ": cannot close the file in memory");
    discard();
    throw std::runtime_error(msg);
  }
  if (const std::string why = write_all(temp_, image); !why.empty()) {
    discard();
    throw WriteError(path_ + ": cannot write (" + temp_ + "): " + why);
  }
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    const int err = errno;
    discard();
    throw WriteError(path_ + ": cannot rename '" + temp_ + "' into place: " + std::strerror(err));
  }
  committed_ = true;
  // Make the rename itself durable; failure here leaves a complete file.
  (void)sync_path(directory_of(path_), true);
}

}  // namespace vt::io::h5
