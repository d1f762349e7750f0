// Builds a Model and its initial State from parts: rigid bodies of mass
// points, particles, springs, wheels. Computes mass, centre of mass and
// inertia from the points (report eqs. 3-5) and checks what the engine
// relies on (positive mass, invertible inertia, valid indices); throws
// std::invalid_argument naming the part otherwise.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"

namespace groundsim {

struct BodySpec {
  std::string name;
  std::vector<Vec3> points;        // m      in the body's reference frame
  std::vector<double> masses;      // kg     one per point (>= 0; attachment points have 0)
  std::vector<bool> contact;       // -      one per point
  // optional, one per point: false = the point only lends its mass to the
  // body's mass and inertia and is not simulated (a continuous wheel's rim)
  std::vector<bool> simulate;
  Vec3 origin = Vec3::Zero();      // m      world position of the reference frame
  Quat orientation = Quat::Identity();
  Vec3 velocity = Vec3::Zero();    // m/s    of the centre of mass
  Vec3 angular_velocity = Vec3::Zero();  // rad/s, world
};

struct BuiltModel {
  std::shared_ptr<const Model> model;
  State initial;
};

class ModelBuilder {
 public:
  ModelBuilder(Options opt, GroundPtr ground);

  // Returns the body index; its points get consecutive indices starting at
  // *first_point. Point offsets are stored relative to the centre of mass.
  int addBody(const BodySpec& spec, int* first_point = nullptr);
  int addParticle(double mass, const Vec3& position, const Vec3& velocity, bool contact = true);
  int addSpring(const Spring& s);
  int addWheel(const Wheel& w);
  // Marks a point as turning with a wheel's steering about pivot (body frame
  // of the point's body, same convention as its offsets).
  void setSteered(int point, int wheel, const Vec3& pivot_in_reference_frame);

  const Model& model() const { return m_; }
  // Initial world position of a point.
  Vec3 pointPosition(int point) const;
  // Reference frame -> centre of mass offset of a body, in its frame.
  Vec3 bodyComOffset(int body) const { return com_offsets_[body]; }
  int beginVehicle(const std::string& name);  // following wheels belong to it
  void setVehicleBody(int body);
  // Registers a road car (road_car_builder.cpp) with its initial states.
  void addRoadCar(const RoadCar& car, const std::array<double, kRoadCarStates>& initial);

  // Contact between bodies (collision/collision.hpp). A group per vehicle
  // or object; colliders and probes name bodies by index and give offsets
  // from the body's centre of mass in its frame (bodyComOffset converts
  // from the reference frame), or world ones when static.
  int addCollisionGroup(const CollisionGroup& g);
  void addCollider(Collider c);
  void addProbe(Probe p);
  void addObject(SceneObject o);

  BuiltModel build();

 private:
  Model m_;
  std::vector<double> y_;  // initial state, grown as parts are added
  std::vector<Vec3> com_offsets_;
  std::vector<Vec3> particle_pos_, particle_vel_;
  std::vector<double> aux_;  // road-car states
  int current_vehicle_ = -1;

};

}  // namespace groundsim
