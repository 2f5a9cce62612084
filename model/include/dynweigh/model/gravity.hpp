#pragma once
// Standard gravity, m/s^2: the model's falls, flows and impulses are reckoned with it. A constant,
// so the let-through's integral and the fall times fold it in.
namespace dynweigh::model {

template <typename Scalar>
constexpr Scalar kGravity = Scalar(9.81);

}  // namespace dynweigh::model
