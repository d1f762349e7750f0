// The cache of choices (accuracy/choice_cache.hpp): the second choice for
// the same content is the first's, made without a pilot; anything that
// decides a choice (the document, the tolerance, the ground file's
// contents, the pilot's options) makes another key.
#include <gtest/gtest.h>

#include <memory>

#include "accuracy/choice_cache.hpp"
#include "scenes.hpp"

namespace groundsim::accuracy {
namespace {

TEST(ChoiceCache, TheSecondChoiceOfTheSameScenarioIsTheFirstWithoutAPilot) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=2"});
  ChoiceCache cache;
  const Choice first = cache.choose(s, 0.01, {});
  EXPECT_FALSE(first.from_cache);
  const Choice again = cache.choose(test::config("sedan_slalom.json", {"duration=2"}), 0.01, {});
  EXPECT_TRUE(again.from_cache);
  EXPECT_EQ(again.integrator, first.integrator);
  EXPECT_EQ(again.dt, first.dt);
  EXPECT_EQ(again.contact_substeps, first.contact_substeps);
  EXPECT_EQ(again.model, first.model);
  EXPECT_EQ(again.predicted_error, first.predicted_error);
  EXPECT_EQ(again.scenario.document, first.scenario.document);
  EXPECT_EQ(cache.size(), 1u);
  // another tolerance, another document: a pilot each
  EXPECT_FALSE(cache.choose(s, 0.1, {}).from_cache);
  EXPECT_FALSE(cache.choose(test::config("sedan_slalom.json", {"duration=1.5"}), 0.01, {}).from_cache);
  EXPECT_EQ(cache.size(), 3u);
}

TEST(ChoiceCache, KeysTellTheGroundFilesContentsAndThePilotsOptions) {
  const scenario::Scenario s = test::config("hills.json", {"duration=1"});
  ASSERT_TRUE(s.ground.heightfield);
  const std::string key = choiceKey(s, 0.01, {});
  EXPECT_EQ(choiceKey(test::config("hills.json", {"duration=1"}), 0.01, {}), key);
  // the same document over a heightfield one sample higher
  scenario::Scenario other = s;
  HeightSamples samples;
  samples.nx = s.ground.heightfield->nx();
  samples.ny = s.ground.heightfield->ny();
  samples.cell = s.ground.heightfield->cell();
  samples.x0 = s.ground.heightfield->x0();
  samples.y0 = s.ground.heightfield->y0();
  samples.heights.assign(static_cast<size_t>(samples.nx) * samples.ny, 1.0f);
  other.ground.heightfield = std::make_shared<const HeightfieldGround>(samples);
  EXPECT_NE(choiceKey(other, 0.01, {}), key);
  PilotOptions o;
  o.safety = 2.0;
  EXPECT_NE(choiceKey(s, 0.01, o), key);
  EXPECT_NE(choiceKey(s, 0.02, {}), key);
}

TEST(ChoiceCache, HoldsAtMostItsEntries) {
  ChoiceCache cache(2);
  for (double d : {1.0, 1.25, 1.5}) cache.choose(test::config("sedan.json", {"duration=" + std::to_string(d)}), 0.1, {});
  EXPECT_EQ(cache.size(), 2u);
  // the oldest went; the newest stays
  EXPECT_TRUE(cache.choose(test::config("sedan.json", {"duration=" + std::to_string(1.5)}), 0.1, {}).from_cache);
  EXPECT_FALSE(cache.choose(test::config("sedan.json", {"duration=" + std::to_string(1.0)}), 0.1, {}).from_cache);
}

}  // namespace
}  // namespace groundsim::accuracy
