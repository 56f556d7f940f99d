// Atomic creation of an HDF5 file (DESIGN §7): everything is written to
// `<path>.tmp.<pid>` in the same directory; commit() closes it, fsyncs it,
// renames it over `path` and fsyncs the directory. A reader therefore sees
// either the old file or the complete new one, never a partial file. If
// commit() is not reached (exception) or fails, the temporary file is
// removed.
#pragma once

#include <string>

#include "virtual_triaxial/io/hdf5_group.h"

namespace vt::io::h5 {

class AtomicFile {
 public:
  /// Creates the temporary file; throws naming `path` (and the temporary
  /// file) when the directory is missing or not writable.
  explicit AtomicFile(const std::string& path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Root group of the temporary file ("/"); errors name the final path.
  const Group& root() const { return root_; }
  const std::string& path() const { return path_; }
  const std::string& temp_path() const { return temp_; }
  /// Close, sync and rename into place. Every group/dataset handle opened
  /// from root() must be closed (out of scope) before this.
  void commit();

 private:
  void discard() noexcept;

  std::string path_, temp_;
  Handle file_;
  Group root_;
  bool committed_ = false;
};

}  // namespace vt::io::h5
