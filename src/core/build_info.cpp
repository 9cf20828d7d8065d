#include "core/build_info.h"

#include "restir_build_id.h"  // generated into the build tree; the only includer, so a new id recompiles one file

namespace rl {

const char* build_id() { return RESTIR_BUILD_ID; }

}  // namespace rl
