// Writing the film to disk: EXR as scene-linear float with the AOVs as extra
// channels (OpenImageIO) and, given a part record, the raw sums that merging render
// parts needs (film/render_part.h), PNG through an OpenColorIO view transform from Blender's
// own config, so a PNG looks as Blender would save it.
#pragma once
#include <string>
#include "film/film.h"
#include "film/render_part.h"

namespace rdv {

// view: "Standard", "Filmic", ... (a view of the config's default display).
// Returns warnings (e.g. no OCIO config found, fell back to plain sRGB).
// part: written into an EXR (ignored for PNG) when given.
std::string write_image(const Film &film, const std::string &path, const std::string &view,
                        const PartRecord *part = nullptr);
// Where Blender's config.ocio is: $OCIO, else the blender package's datafiles.
std::string find_ocio_config();

}  // namespace rdv
