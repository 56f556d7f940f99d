// Numbers in one-line messages and JSON text: printf's %.<digits>g, the
// shortest form with that many significant digits (6 is printf's default
// and std::ostream's). One home for the form every reader, check and tool
// of this library prints.
#pragma once

#include <cstdio>
#include <string>

namespace vt::io {

inline std::string number_text(double v, int significant_digits = 6) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", significant_digits, v);
  return b;
}

}  // namespace vt::io
