// Atomic, checked writing of a small text file: the content goes to
// `<path>.tmp.<pid>` in the same directory, every write(2) and the close(2)
// are checked, then the file is renamed over `path`. A reader (ParaView
// polling a time series, the section renderer) sees the old file or the
// complete new one, never a partial one. Not fsynced: the files are views
// of a run, rewritten by the next snapshot; a crash may lose the last one
// but never leaves a truncated file under the final name.
#pragma once

#include <string>

namespace vt::io {

/// Throws std::runtime_error "<path>: <reason>" (the temporary file is removed).
void write_text_file_atomically(const std::string& path, const std::string& content);

}  // namespace vt::io
