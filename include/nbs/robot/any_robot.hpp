// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// `AnyRobot`: a type-erased `Robot` (a shared, immutable model behind a virtual interface), so that code compiled
/// once — the run-time planner facade, the command-line tools — can plan for a robot chosen at run time (a URDF
/// arm of nbs::kdl, FreeFlyingSensor, a test robot). Copies share the model. Const members may run concurrently if
/// the wrapped model's do.

#include <memory>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "nbs/robot/robot.hpp"

namespace nbs {

class AnyRobot {
public:
  /// Wraps a copy of `robot`.
  template <Robot R>
    requires(!std::same_as<std::remove_cvref_t<R>, AnyRobot>)
  explicit AnyRobot(R robot) : model_(std::make_shared<const Model<R>>(std::move(robot))) {}

  [[nodiscard]] std::size_t joint_count() const { return model_->joint_count(); }
  [[nodiscard]] JointLimits joint_limits() const { return model_->joint_limits(); }
  [[nodiscard]] Pose fk(const JointVector& q) const { return model_->fk(q); }
  [[nodiscard]] std::optional<JointVector> ik(const Pose& T_WS, const JointVector& seed) const {
    return model_->ik(T_WS, seed);
  }
  [[nodiscard]] std::vector<PlacedShape> collision_shapes(const JointVector& q) const {
    return model_->collision_shapes(q);
  }
  [[nodiscard]] Pose hand_eye() const { return model_->hand_eye(); }

private:
  struct Interface {
    virtual ~Interface() = default;
    [[nodiscard]] virtual std::size_t joint_count() const = 0;
    [[nodiscard]] virtual JointLimits joint_limits() const = 0;
    [[nodiscard]] virtual Pose fk(const JointVector& q) const = 0;
    [[nodiscard]] virtual std::optional<JointVector> ik(const Pose& T, const JointVector& seed) const = 0;
    [[nodiscard]] virtual std::vector<PlacedShape> collision_shapes(const JointVector& q) const = 0;
    [[nodiscard]] virtual Pose hand_eye() const = 0;
  };
  template <class R>
  struct Model final : Interface {
    explicit Model(R r) : robot(std::move(r)) {}
    std::size_t joint_count() const override { return robot.joint_count(); }
    JointLimits joint_limits() const override { return robot.joint_limits(); }
    Pose fk(const JointVector& q) const override { return robot.fk(q); }
    std::optional<JointVector> ik(const Pose& T, const JointVector& seed) const override { return robot.ik(T, seed); }
    std::vector<PlacedShape> collision_shapes(const JointVector& q) const override {
      return robot.collision_shapes(q);
    }
    Pose hand_eye() const override { return robot.hand_eye(); }
    R robot;
  };
  std::shared_ptr<const Interface> model_;
};

static_assert(Robot<AnyRobot>);

}  // namespace nbs
