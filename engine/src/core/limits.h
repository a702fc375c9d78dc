// The engine's input limits: how deep a description may nest, how much geometry a
// generated shape may make, and how much memory one allocation may ask for. Every
// recursive walk over user input (JSON, shader trees, texture graphs) is bounded by
// one of these, so a hostile scene gets an error naming the object (status
// RDV_ERROR_LIMIT) instead of a stack overflow, a hang or the OOM killer.
// docs/scene-format.md ("Limits") lists them for users.
#pragma once
#include <nlohmann/json.hpp>
#include <cstdint>
#include <string>
#include <string_view>

namespace rdv {

// JSON nesting (arrays and objects) of a parameter description or a scene file.
// A legitimate material nests one level per Mix / Add shader and per texture node.
constexpr int kMaxJsonDepth = 1000;
// Mix / Add shaders nested in one material (Cycles' own SVM stack holds 255 values).
constexpr int kMaxShaderNesting = 256;
// Texture nodes on one path from a material input down to a leaf (evaluation recurses
// per node on the render threads' stacks).
constexpr int kMaxTextureDepth = 256;
// Samples per pixel: the film counts them in float, exact up to 2^24 (a time-limited
// render halts there too).
constexpr uint32_t kMaxSamplesPerPixel = uint32_t(1) << 24;
// Texture-node evaluations per shading point for one material input: an image node
// evaluates its vector three times (at the point and at its footprint's two offsets), a
// bump node its height three times, so chains of them multiply (30 nested bumps: 3^30).
constexpr double kMaxTextureEvaluations = 1e6;
// Triangles of one generated shape (sphere, disk) in a scene file.
constexpr uint64_t kMaxGeneratedTriangles = uint64_t(1) << 24;

// Nesting depth of JSON text: brackets outside strings, in one pass without parsing
// (so 1e5 nested arrays cost microseconds, and no recursive JSON code ever sees them).
// Stops counting at limit + 1.
int json_text_depth(std::string_view text, int limit = kMaxJsonDepth);
// Nesting depth of a parsed value, without recursion; stops at limit + 1.
int json_depth(const nlohmann::json &j, int limit = kMaxJsonDepth);
// Fails (RDV_ERROR_LIMIT) naming `what` when the text nests deeper than kMaxJsonDepth.
void check_json_depth(std::string_view text, const std::string &what);

// Bytes the engine may allocate for one object: the machine's physical memory, or
// RDV_MEMORY_LIMIT_MB when set (a cap for shared machines, and for tests).
double memory_budget_bytes();
// Fails (RDV_ERROR_LIMIT) when `bytes` exceed the budget: "<what>: <for_what> needs
// about 292.0 GB, more than the 23.4 GB of memory available to the engine".
void check_memory(const std::string &what, const std::string &for_what, double bytes);
// "292.0 GB", "18.4 MB": for messages.
std::string format_bytes(double bytes);

}  // namespace rdv
