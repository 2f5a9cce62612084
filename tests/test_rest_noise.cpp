// The scale's noise at rest (firmware/include/dynweigh/firmware/rest_noise.hpp): the quietest rest
// kept, so that a rest taken while the platform still rings does not loosen the certification of
// the next fill.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dynweigh/firmware/rest_noise.hpp"

namespace dynweigh::firmware {
namespace {

void rest(RestNoise& noise, std::uint32_t samples, double noise_g, double ring_g, std::uint32_t seed) {
  std::mt19937 generator(seed);
  std::normal_distribution<double> draw(0.0, noise_g);
  noise.restart();
  for (std::uint32_t n = 0; n < samples; ++n) {
    noise.push(float(draw(generator) + ring_g * std::sin(2.0 * M_PI * 8.0 * 0.01 * n)));
  }
}

TEST(RestNoise, IsTheNoiseOfAQuietRest) {
  RestNoise noise;
  rest(noise, 200, 0.5, 0.0, 1);
  noise.restart();  // the weight moved: the rest of 200 samples is kept
  EXPECT_NEAR(noise.rms_g(), 0.5, 0.05);
}

TEST(RestNoise, ARingingRestDoesNotRaiseIt) {
  RestNoise noise;
  rest(noise, 200, 0.5, 0.0, 1);
  rest(noise, 200, 0.5, 4.0, 2);  // between two fills: within the stable band, still ringing
  noise.keep_this_rest();
  EXPECT_NEAR(noise.rms_g(), 0.5, 0.05);
}

TEST(RestNoise, AShortRestCountsOnlyWhenADoseOpensFromIt) {
  RestNoise noise;
  rest(noise, RestNoise::kLeastSamples - 1, 0.5, 0.0, 3);
  noise.restart();
  EXPECT_EQ(noise.rms_g(), 0.0f) << "no rest was long enough yet";
  rest(noise, 30, 0.5, 0.0, 4);
  noise.keep_this_rest();
  EXPECT_NEAR(noise.rms_g(), 0.5, 0.15);
}

// Days at rest: the mean square runs over the last samples, and keeps its resolution.
TEST(RestNoise, ALongRestKeepsItsResolution) {
  RestNoise noise;
  rest(noise, 3'000'000, 0.2, 0.0, 5);
  noise.keep_this_rest();
  EXPECT_NEAR(noise.rms_g(), 0.2, 0.03);
}

}  // namespace
}  // namespace dynweigh::firmware
