// Every JSON scene shipped in scenes/ loads without problems and renders finite.
#include <gtest/gtest.h>
#include <filesystem>
#include "render_helpers.h"

namespace test_scenes {

using namespace rdv::test;

TEST(Scenes, EveryShippedSceneRendersFinite) {
  int count = 0;
  for (const auto &entry : std::filesystem::directory_iterator(source_path("scenes"))) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    Image img = render_file(entry.path().string(), R"({"width":32,"height":24,"samples":4,"time_limit":0})");
    EXPECT_TRUE(img.all_finite());
    EXPECT_EQ(img.progress.samples_dropped, 0u);
    EXPECT_EQ(img.warnings, "") << "shipped scenes should load cleanly";
    double mean = img.channel_mean(0) + img.channel_mean(1) + img.channel_mean(2);
    EXPECT_GT(mean, 0.0) << "the image is black";
    ++count;
  }
  EXPECT_GE(count, 3);
}

}  // namespace test_scenes
