#pragma once
// OIML R61 (automatic gravimetric filling instruments), class X(1): the maximum permissible deviation
// of a fill from the mean of the fills, at initial verification and in service, for a fill of m
// grams. Class X(x) multiplies both by x. The firmware holds a dose that ends short by more than
// X(5) to be a failed dose; the bench grades strategies by the class they reach.
namespace dynweigh::model {

template <typename Scalar>
struct OimlR61Limits {
  Scalar initial_verification_g;
  Scalar in_service_g;
};

template <typename Scalar>
OimlR61Limits<Scalar> oiml_r61_x1_limits(Scalar m) {
  if (m <= Scalar(50)) return {Scalar(0.063) * m, Scalar(0.09) * m};
  if (m <= Scalar(100)) return {Scalar(3.15), Scalar(4.5)};
  if (m <= Scalar(200)) return {Scalar(0.0315) * m, Scalar(0.045) * m};
  if (m <= Scalar(300)) return {Scalar(6.3), Scalar(9.0)};
  if (m <= Scalar(500)) return {Scalar(0.021) * m, Scalar(0.03) * m};
  if (m <= Scalar(1000)) return {Scalar(10.5), Scalar(15.0)};
  if (m <= Scalar(10000)) return {Scalar(0.0105) * m, Scalar(0.015) * m};
  if (m <= Scalar(15000)) return {Scalar(105.0), Scalar(150.0)};
  return {Scalar(0.007) * m, Scalar(0.01) * m};
}

}  // namespace dynweigh::model
