// Atomic creation of an HDF5 file (DESIGN §7). The file is built in memory
// (HDF5 core driver, no backing store); commit() takes its image
// (H5Fget_file_image), writes it to `<path>.tmp.<pid>` in the same
// directory with checked POSIX writes, fsyncs it, renames it over `path`
// and fsyncs the directory. A reader therefore sees either the old file or
// the complete new one, never a partial file. HDF5 itself never writes to
// the disk, so a full disk (ENOSPC) or any other write error is a WriteError
// with one line naming the file and the reason (strerror), the temporary
// file is removed and the library is left in a clean state (an HDF5 file
// whose close failed on a full disk could not be closed at all, and the
// library crashed at exit).
#pragma once

#include <stdexcept>
#include <string>

#include "virtual_triaxial/io/hdf5_group.h"

namespace vt::io {

/// An output file could not be written (full disk, no permission, ...);
/// what() is one line naming the file and the reason. Files written before
/// are intact.
class WriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace vt::io

namespace vt::io::h5 {

class AtomicFile {
 public:
  /// Creates the file in memory; throws WriteError naming `path` when the
  /// directory is missing or not writable.
  explicit AtomicFile(const std::string& path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Root group of the temporary file ("/"); errors name the final path.
  const Group& root() const { return root_; }
  const std::string& path() const { return path_; }
  const std::string& temp_path() const { return temp_; }
  /// Write to the temporary file, sync and rename into place (WriteError
  /// on failure). Every group/dataset handle opened from root() must be
  /// closed (out of scope) before this.
  void commit();

 private:
  void discard() noexcept;

  std::string path_, temp_;
  Handle file_;
  Group root_;
  bool committed_ = false;
};

}  // namespace vt::io::h5
