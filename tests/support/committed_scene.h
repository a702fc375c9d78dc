// A JSON scene loaded through the C ABI and committed, with the C++ Scene behind the
// handle, for tests of the scene's own queries (internal: api/handles.h).
#pragma once
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "api/handles.h"
#include "scene_file.h"

namespace rdv::test {

struct CommittedScene {
  rdv_scene *handle = nullptr;
  explicit CommittedScene(const nlohmann::json &doc) {
    rdv_scene_create(&handle);
    auto loaded = rdv_tools::load_scene_json(doc.dump(), ".", handle);
    EXPECT_TRUE(loaded.problems.empty());
    EXPECT_EQ(rdv_scene_commit(handle), RDV_OK) << rdv_last_error();
  }
  ~CommittedScene() { rdv_scene_destroy(handle); }
  CommittedScene(const CommittedScene &) = delete;
  CommittedScene &operator=(const CommittedScene &) = delete;
  const Scene &scene() const { return *handle->scene; }
};

}  // namespace rdv::test
