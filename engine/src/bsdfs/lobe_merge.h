// When a shading point's lobes or layers outgrow the Bsdf's fixed capacity (a node
// tree mixing many closures), lobes of one kind are merged instead of dropped, so the
// material keeps its energy. The merged lobe's f is the sum of the two where they
// differ only in linear terms (colour, closure weight, Schlick f0): diffuse-like lobes
// of equal roughness, GGX lobes of equal roughness and Fresnel kind, dielectrics of
// equal IOR. Otherwise its shape parameters (roughness, IOR) are averaged, weighted by
// each lobe's share of the energy: approximate, and the material warns when parsed.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv {

// lobes[0, n) is full (n == capacity). Either merges `incoming` into one of them
// (returns -1) or merges two of them, freeing a slot (returned) for `incoming`.
// weights are the lobes' sample weights: merged lobes add theirs.
int make_room_for_lobe(Lobe *lobes, float *weights, int n, const Lobe &incoming, float incoming_weight);

// layers[0, n) is full: the index of the existing layer most like `incoming` (the
// lobes below it share that one's albedo scaling).
int closest_layer(const LayerAbove *layers, int n, const LayerAbove &incoming);

}  // namespace rdv
