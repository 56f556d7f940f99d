// Atomic, checked writing of a small text file (summary.json, protocol.yaml):
// written to <path>.tmp.<pid>, fsynced, renamed over `path`. On a full disk
// or any other write error the old file stays as it was, the temporary file
// is removed and io::WriteError says which file and why in one line.
#pragma once

#include <string>

#include "virtual_triaxial/io/hdf5_atomic_file.h"  // io::WriteError

namespace vt::io {

/// Replaces `path` by `text` atomically; throws WriteError.
void write_text_atomic(const std::string& path, const std::string& text);

}  // namespace vt::io
