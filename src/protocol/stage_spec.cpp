#include "virtual_triaxial/protocol/stage_spec.h"

namespace vt::protocol {

const char* to_string(StageType t) {
  switch (t) {
    case StageType::IsotropicCompression: return "isotropic_compression";
    case StageType::UndrainedShear: return "undrained_shear";
    case StageType::Relax: return "relax";
  }
  return "?";
}

}  // namespace vt::protocol
