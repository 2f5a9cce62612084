// The plant family's speed comparison line (tools/bench/family_comparison.hpp), from cell lines
// written by hand: what counts as faster at an equal or better class, in each reading.
#include <gtest/gtest.h>

#include "family_comparison.hpp"

namespace dynweigh::tools {
namespace {

std::string cell(const char* strategy, const char* plant, const char* steady, const char* time) {
  return std::string("strategy=") + strategy + " plant=" + plant + " target_g=500 class_first=X(1) class_steady=" +
         steady + " time_ratio=" + time + " topups=0 first_error_g=1.0 steady_bias_g=0.5 steady_maxdev_g=2.0 "
         "failed=0 failure=-";
}

TEST(FamilyComparison, CountsTheCellsWhereTheModelIsFasterAtAnEqualOrBetterClass) {
  const std::vector<std::string> lines = {
      // faster and as good: counts in every reading
      cell("model", "random-1", "X(1)", "2.000"), cell("twostage", "random-1", "X(1)", "2.500"),
      cell("pac", "random-1", "X(2)", "2.100"),
      // faster, but a baseline graded X(0.2) against the model's X(0.5): only within the asked X(1)
      cell("model", "random-2", "X(0.5)", "2.000"), cell("twostage", "random-2", "X(0.2)", "2.500"),
      cell("pac", "random-2", "X(1)", "3.000"),
      // better class but slower than one baseline of a worse class: not faster, but unbeaten
      cell("model", "random-3", "X(1)", "3.000"), cell("twostage", "random-3", "X(5)", "2.900"),
      cell("pac", "random-3", "none", "0.000"),
      // no class: worse than any, whatever the time, and beaten
      cell("model", "random-4", "none", "1.000"), cell("twostage", "random-4", "X(5)", "2.000"),
      cell("pac", "random-4", "X(5)", "2.000"),
      // the learning variant and the oracle are no baselines
      cell("model", "random-5", "X(1)", "2.000"), cell("learn", "random-5", "X(1)", "1.000"),
      cell("oracle-scale", "random-5", "X(0.1)", "1.000"), cell("twostage", "random-5", "none", "0.000"),
      cell("pac", "random-5", "X(2)", "2.200")};
  const auto line = family_comparison_summary(lines);
  ASSERT_TRUE(line.has_value());
  EXPECT_EQ(*line,
            "summary comparison=model baselines=pac,twostage cells=5 faster_cells=2 faster_share=0.400 "
            "faster_cells_x1=3 faster_share_x1=0.600 unbeaten_cells=4 unbeaten_share=0.800");
}

TEST(FamilyComparison, NeedsTheModelAndABaseline) {
  EXPECT_FALSE(family_comparison_summary({cell("model", "random-1", "X(1)", "2.0")}).has_value());
  EXPECT_FALSE(family_comparison_summary({cell("twostage", "random-1", "X(1)", "2.0")}).has_value());
  EXPECT_FALSE(family_comparison_summary({cell("model", "random-1", "X(1)", "2.0"),
                                          cell("learn", "random-1", "X(1)", "1.0")})
                   .has_value());
  EXPECT_FALSE(family_comparison_summary({"", "summary strategy=model", "garbage"}).has_value());
}

}  // namespace
}  // namespace dynweigh::tools
