#include "drivers/policy_driver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace groundsim::drivers {
PolicyDriver::PolicyDriver(std::shared_ptr<const Policy> policy, std::shared_ptr<const TrackCourse> course, int body,
                           double skill)
    : policy_(std::move(policy)), course_(std::move(course)), body_(body), skill_(std::clamp(skill, 0.0, 1.0)) {
  if (policy_->actionSize() != 3)
    throw PolicyError("policy file: action_low: " + std::to_string(policy_->actionSize()) +
                      " actions; a driver commands car_controls (throttle, brake, steer)");
  const int t = static_cast<int>(policy_->trackAhead().size());
  int size = 0;
  const std::vector<std::string>& f = policy_->features();
  for (std::size_t i = 0; i < f.size(); ++i) {
    const std::string& n = f[i];
    if (n == "up_body") parts_.push_back(Part::UpBody), size += 3;
    else if (n == "velocity_body") parts_.push_back(Part::VelocityBody), size += 3;
    else if (n == "angular_velocity_body") parts_.push_back(Part::AngularVelocityBody), size += 3;
    else if (n == "speed") parts_.push_back(Part::Speed), size += 1;
    else if (n == "previous_action") parts_.push_back(Part::PreviousAction), size += 3;
    else if (n == "track_ahead") parts_.push_back(Part::TrackAhead), size += 2 * t;
    else if (n == "track_pose") parts_.push_back(Part::TrackPose), size += 3;
    else if (n == "track_curvature") parts_.push_back(Part::TrackCurvature), size += t;
    else if (n == "next_gate") parts_.push_back(Part::NextGate), size += 2;
    else
      throw PolicyError("policy file: observation/" + std::to_string(i) + ": feature \"" + n +
                        "\" is not one a driver in a session senses (up_body, velocity_body, angular_velocity_body, "
                        "speed, previous_action, track_ahead, track_pose, track_curvature, next_gate)");
  }
  if (size != policy_->obsSize())
    throw PolicyError("policy file: normalise/mean: " + std::to_string(policy_->obsSize()) +
                      " values, its features make " + std::to_string(size));
  feature_.assign(static_cast<std::size_t>(size), 0.0);
  obs_.assign(static_cast<std::size_t>(size), 0.0f);
  action_.assign(3, 0.0f);
  previous_.assign(3, 0.0f);
  reach_ = 50.0 + 100.0 * policy_->controlPeriod() * policy_->dt();  // as the environment's
}

void PolicyDriver::relocate() {
  located_ = false;
  std::fill(previous_.begin(), previous_.end(), 0.0f);
}

const std::vector<float>& PolicyDriver::observe(const Model& m, const State& s) {
  const BodyView car = viewBody(m, s.y, body_);
  const Vec2 c{car.c.x(), car.c.y()};
  at_ = located_ ? course_->line().locate(c, at_.s, reach_) : course_->line().locate(c);
  located_ = true;
  const std::vector<double>& ahead = policy_->trackAhead();
  double* o = feature_.data();
  for (Part p : parts_) {
    switch (p) {
      case Part::UpBody: upBody(car, o), o += 3; break;
      case Part::VelocityBody: velocityBody(car, o), o += 3; break;
      case Part::AngularVelocityBody: angularVelocityBody(car, o), o += 3; break;
      case Part::Speed: *o++ = car.v.norm(); break;
      case Part::PreviousAction:
        for (float a : previous_) *o++ = a;
        break;
      case Part::TrackAhead: trackAhead(*course_, at_, car, ahead, o), o += 2 * ahead.size(); break;
      case Part::TrackPose: trackPose(*course_, at_, car, o), o += 3; break;
      case Part::TrackCurvature: trackCurvature(*course_, at_, ahead, o), o += ahead.size(); break;
      case Part::NextGate: nextGate(*course_, at_, car, o), o += 2; break;
    }
  }
  for (std::size_t i = 0; i < feature_.size(); ++i) obs_[i] = publishedFloat(feature_[i]);
  return obs_;
}

Pedals PolicyDriver::drive(const Model& m, const State& s) {
  policy_->act(observe(m, s).data(), action_.data());
  action_[0] = std::min(action_[0], static_cast<float>(skill_));  // the skill caps the throttle
  previous_ = action_;
  Pedals p;
  p.throttle = action_[0];
  p.brake = action_[1];
  p.steer = action_[2];
  return p;
}

}  // namespace groundsim::drivers
