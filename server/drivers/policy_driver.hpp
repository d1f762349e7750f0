// A trained policy at the wheel (docs/drivers.md, "Trained drivers"): it
// senses its car exactly as the task it was trained on observed it (the
// same functions: drivers/track_course.hpp, rounded to float as the
// environment publishes), acts every control period of its training, and
// drives at a skill that caps its throttle.
#pragma once

#include <memory>
#include <vector>

#include "drivers/driver.hpp"
#include "drivers/policy.hpp"
#include "drivers/track_course.hpp"

namespace groundsim::drivers {

class PolicyDriver : public Driver {
 public:
  // Throws PolicyError when the policy observes what a car in a session
  // cannot sense (its goal, other agents, wheels, the episode's time) or
  // does not command car_controls (throttle, brake, steer).
  PolicyDriver(std::shared_ptr<const Policy> policy, std::shared_ptr<const TrackCourse> course, int body,
               double skill = 1.0);

  Pedals drive(const Model& m, const State& s) override;
  void relocate() override;

  // The observation of the car in state s, as the task's environment
  // would publish it; locates the car on the track (near where it was).
  const std::vector<float>& observe(const Model& m, const State& s);
  // The actions taken so far: the previous one (what previous_action reads).
  const std::vector<float>& previousAction() const { return previous_; }

 private:
  enum class Part { UpBody, VelocityBody, AngularVelocityBody, Speed, PreviousAction, TrackAhead, TrackPose,
                    TrackCurvature, NextGate };
  std::shared_ptr<const Policy> policy_;
  std::shared_ptr<const TrackCourse> course_;
  int body_ = 0;
  double skill_ = 1.0;
  double reach_ = 50.0;           // m  how far along the line a car is looked for from where it was
  std::vector<Part> parts_;
  std::vector<double> feature_;   // the observation in double, before rounding
  std::vector<float> obs_, action_, previous_;
  TrackLine::Where at_;
  bool located_ = false;
};

}  // namespace groundsim::drivers
