#pragma once
// What a reader of a render should recognise: a forearm that tapers to the wrist, a palm in the exosuit's glove, four
// fingers and a thumb in a relaxed pose, the elbow band, the two IMUs on the dorsal side, and each muscle's mounts as
// markers on stand-offs (Section Exosuit design). Drawing only: every geom has no contact and no mass (the model's
// inertias are given explicitly, model_builder.cc), so the dynamics are the same with or without them
// (tests/sim/anatomy_visuals_test.cc).
//
// Sizes scale with the hand's length (placement file `hand.length_cm`); the forearm and palm are thinned where a mount
// would otherwise sit inside them, so each mount shows where the muscle meets the glove or the band.

#include <string>

#include "sim/device.h"

namespace softwrist::sim {

struct AnatomyVisuals {
  std::string assets;         // <asset> children: meshes, textures, materials
  std::string forearm_geoms;  // children of the forearm body (frame of model_builder.h)
  std::string hand_geoms;     // children of the hand body
};

AnatomyVisuals anatomy_visuals(const DeviceDescription& device);

// The forearm's drawn length [m]: 1.4 hand lengths (Drillis & Contini 1966: forearm 0.146, hand 0.108 of body
// height), and at least past the farthest forearm mount.
double drawn_forearm_length(const DeviceDescription& device);

}  // namespace softwrist::sim
