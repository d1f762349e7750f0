// The road car's reduced mass matrix: a part of its model, built once
// (road_car_builder.cpp) and read by each evaluation (forces/road_cars.cpp).
#include "physics/road_car/road_car.hpp"

namespace groundsim {

Eigen::Matrix<double, 6, 6> reducedMassBody(const RoadCar& rc, double mass, const Mat3& inertia) {
  Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
  M.topLeftCorner<3, 3>() = mass * Mat3::Identity();
  M.bottomRightCorner<3, 3>() = inertia;
  for (int w = 0; w < 4; ++w) {
    Eigen::Matrix<double, 6, 1> j;
    j << Vec3::UnitZ(), rc.hub[w].cross(Vec3::UnitZ());
    M.noalias() -= rc.p.wheel_mass * j * j.transpose();
  }
  return M;
}

}  // namespace groundsim
