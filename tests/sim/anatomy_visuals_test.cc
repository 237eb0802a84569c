// The drawn hand and forearm (sim/anatomy_visuals.h): drawing only, so the model moves exactly as without it.

#include "sim/anatomy_visuals.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "sim/model.h"
#include "sim/model_builder.h"

namespace softwrist::sim {
namespace {

const PluginSet& plugins() {
  static const PluginSet set = PluginSet::Default();
  return set;
}

Model build(const DeviceDescription& device, bool anatomy) {
  return Model::FromXml(build_model_xml(device, {.anatomy = anatomy}), plugins());
}

// Two seconds from rest with the flexor and the ulnar muscle inflating: qpos, qvel and the activations, step by step.
std::vector<double> trajectory(const Model& model) {
  const Data data = make_data(model);
  data->ctrl[0] = 137.0;
  data->ctrl[2] = 60.0;
  std::vector<double> states;
  for (int step = 0; step < 2000; ++step) {
    mj_step(model.get(), data.get());
    for (int i = 0; i < model->nq; ++i) states.push_back(data->qpos[i]);
    for (int i = 0; i < model->nv; ++i) states.push_back(data->qvel[i]);
    for (int i = 0; i < model->na; ++i) states.push_back(data->act[i]);
  }
  return states;
}

// The anatomy adds geoms, but no mass, no inertia and no contact: the bodies' masses and inertias, and a two-second
// trajectory with two muscles pulling, are bit for bit those of the model without it.
TEST(AnatomyVisuals, ChangeNoDynamics) {
  const DeviceDescription device = paper_device();
  const Model drawn = build(device, true), bare = build(device, false);
  EXPECT_GE(drawn->ngeom, bare->ngeom + 20);
  ASSERT_EQ(drawn->nbody, bare->nbody);
  for (int b = 0; b < drawn->nbody; ++b) {
    EXPECT_EQ(drawn->body_mass[b], bare->body_mass[b]) << b;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(drawn->body_inertia[3 * b + k], bare->body_inertia[3 * b + k]) << b;
  }
  EXPECT_EQ(trajectory(drawn), trajectory(bare));
}

// The model runs without MuJoCo's collision detection (model_builder.cc: no geom can collide, and its broadphase was
// 12 % of a diagnosis): the drawn model moves bit for bit as with collision detection on. The bare model, which the
// diagnosis replays, has no meshes, textures or materials to compile.
TEST(AnatomyVisuals, ContactsOffChangeNoDynamicsAndTheBareModelHasNoAssets) {
  const DeviceDescription device = paper_device();
  std::string xml = build_model_xml(device);
  const std::string flag = "\n    <flag contact=\"disable\"/>";
  ASSERT_NE(xml.find(flag), std::string::npos);
  const Model without_collision = Model::FromXml(xml, plugins());
  xml.erase(xml.find(flag), flag.size());
  const Model with_collision = Model::FromXml(xml, plugins());
  EXPECT_TRUE(without_collision->opt.disableflags & mjDSBL_CONTACT);
  EXPECT_FALSE(with_collision->opt.disableflags & mjDSBL_CONTACT);
  EXPECT_EQ(trajectory(without_collision), trajectory(with_collision));
  // What makes it safe: no geom of the generated model can collide. One that should must come with the flag removed.
  for (int g = 0; g < with_collision->ngeom; ++g) {
    const char* name = mj_id2name(with_collision.get(), mjOBJ_GEOM, g);
    EXPECT_EQ(with_collision->geom_contype[g] | with_collision->geom_conaffinity[g], 0)
        << (name ? name : "an unnamed geom")
        << " could collide: remove <flag contact=\"disable\"/> and raise <size njmax nconmax> (model_builder.cc)";
  }
  const Model bare = build(device, false);
  EXPECT_EQ(bare->nmesh, 0);
  EXPECT_EQ(bare->ntex, 0);
  EXPECT_EQ(bare->nmat, 0);
  EXPECT_GT(with_collision->nmesh, 0);
}

// Every drawn geom is out of contact and in the drawing group; the hand has five digits of three segments.
TEST(AnatomyVisuals, AreDrawingOnlyAndComplete) {
  const Model model = build(paper_device(), true);
  for (const char* name : {"forearm", "wrist", "elbow_band", "forearm_imu", "hand", "hand_imu", "thumb_1", "thumb_3",
                           "index_1", "middle_2", "ring_3", "little_3", "flexor_forearm_standoff"}) {
    const int g = model.id(mjOBJ_GEOM, name);
    EXPECT_EQ(model->geom_contype[g], 0) << name;
    EXPECT_EQ(model->geom_conaffinity[g], 0) << name;
    EXPECT_EQ(model->geom_group[g], 1) << name;
  }
}

// Sized from the placement file's hand length: a 15 cm hand's fingers are 15/19 of a 19 cm hand's, in place and
// thickness; the forearm is drawn 1.35 hand lengths long, or past its farthest mount.
TEST(AnatomyVisuals, ScaleWithTheHandLength) {
  DeviceDescription small = paper_device(), large = paper_device();
  small.hand.length = 0.15;
  large.hand.length = 0.19;
  const Model a = build(small, true), b = build(large, true);
  const int ga = a.id(mjOBJ_GEOM, "middle_3"), gb = b.id(mjOBJ_GEOM, "middle_3");
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a->geom_pos[3 * ga + k], b->geom_pos[3 * gb + k] * 15.0 / 19.0, 1e-5) << k;
  EXPECT_NEAR(a->geom_size[3 * ga], b->geom_size[3 * gb] * 15.0 / 19.0, 1e-5);
  EXPECT_DOUBLE_EQ(drawn_forearm_length(large), 0.245 + 0.02);  // the extensor's forearm mount, d1 = 24.5 cm
  for (MuscleMount& m : large.muscles) m.placement.d1 = 0.10;
  EXPECT_DOUBLE_EQ(drawn_forearm_length(large), 1.35 * 0.19);
}

}  // namespace
}  // namespace softwrist::sim
