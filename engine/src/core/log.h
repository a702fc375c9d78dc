// Engine-wide warnings: collected per scene for the user (rdv_scene_messages) and
// echoed to stderr when RDV_VERBOSE is set.
#pragma once
#include <string>

namespace rdv {
void log_warning(const std::string &message);
}  // namespace rdv
