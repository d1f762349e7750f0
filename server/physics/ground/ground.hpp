// The ground is any implicit surface H(x, y, z) = 0; points with H < 0 are
// below it. The core only asks H and grad H at a point (see the report,
// eq. 10), so analytic grounds, parsed expressions and height fields are all
// implementations of one small interface.
//
// A Ground is part of the immutable model and may be shared by simulations
// on several threads: its const methods must be safe to call concurrently.
// A ground that needs evaluation state (a parser's variables and stack)
// keeps it out of the model, in a GroundEvaluator that each simulation's
// Workspace owns (makeEvaluator).
#pragma once

#include <limits>
#include <memory>
#include <string>

#include "physics/base/math.hpp"

namespace groundsim {

// Per-simulation evaluation state of a ground; one thread at a time.
class GroundEvaluator {
 public:
  virtual ~GroundEvaluator() = default;
  virtual double eval(const Vec3& p, Vec3* grad) = 0;
  virtual void heights(const double* x, const double* y, const double* z, int begin, int end,
                       double* H) = 0;
};

class Ground {
 public:
  virtual ~Ground() = default;
  // H at p; writes grad H at p into *grad.
  virtual double eval(const Vec3& p, Vec3* grad) const = 0;
  // H at points [begin, end) of the arrays, without gradients: the contact
  // test for many points at once (analytic grounds override it with a loop
  // the compiler vectorises).
  virtual void heights(const double* x, const double* y, const double* z, int begin, int end,
                       double* H) const;
  // An upper bound on |grad H| over all space, or +inf when none is known.
  // With it, H(c) > L * r proves a ball of radius r about c is above the
  // ground, so its points need no contact evaluation (broad phase).
  virtual double gradientBound() const { return std::numeric_limits<double>::infinity(); }
  // Coulomb mu at contact point p; scene_mu (the scene's contact.friction)
  // unless the ground carries friction patches or a map (surface_friction.hpp).
  virtual double friction(const Vec3& p, double scene_mu) const {
    (void)p;
    return scene_mu;
  }
  // True for a plane n . p - offset (|n| = 1), with n and offset written:
  // the specialised car step (fast_car.hpp) finds circle contacts on it in
  // closed form. Any other ground, including a plane wrapped with friction
  // patches, says false.
  virtual bool asPlane(Vec3* n, double* offset) const {
    (void)n;
    (void)offset;
    return false;
  }
  virtual std::string describe() const = 0;
  // The evaluator a simulation uses in its hot loop; nullptr (the default)
  // means the ground is stateless and eval/heights are called directly.
  virtual std::unique_ptr<GroundEvaluator> makeEvaluator() const { return nullptr; }
};

using GroundPtr = std::shared_ptr<const Ground>;

// A ground with its evaluator, if it has one: what the force loop and the
// scene placement call. Owned by one simulation (or one builder).
class GroundProbe {
 public:
  explicit GroundProbe(const Ground& g) : ground_(&g), evaluator_(g.makeEvaluator()) {}
  double eval(const Vec3& p, Vec3* grad) {
    return evaluator_ ? evaluator_->eval(p, grad) : ground_->eval(p, grad);
  }
  void heights(const double* x, const double* y, const double* z, int begin, int end, double* H) {
    if (evaluator_) evaluator_->heights(x, y, z, begin, end, H);
    else ground_->heights(x, y, z, begin, end, H);
  }
  const Ground& ground() const { return *ground_; }

 private:
  const Ground* ground_;
  std::unique_ptr<GroundEvaluator> evaluator_;
};

// Surface point below (x, y) (solving H(x, y, z) = 0 for z) and unit normal.
bool groundPointBelow(GroundProbe& g, double x, double y, Vec3* point, Vec3* normal);
bool groundPointBelow(const Ground& g, double x, double y, Vec3* point, Vec3* normal);

// n . p - offset, with |n| = 1 (z = 0 is n = (0,0,1), offset 0).
GroundPtr makePlane(const Vec3& normal, double offset);
// Plane through the origin tilted by angle_rad so that the ground descends
// along the horizontal unit direction downhill (the report's eq. 23 is
// angle pi/6, downhill +x: H = z + tan(pi/6) x, normalised here to |grad| = 1).
GroundPtr makeIncline(double angle_rad, const Vec3& downhill);
// z - amplitude * cos(2 pi x / wavelength) (the report's eq. 25: 0.5, 2 pi).
GroundPtr makeCosineWave(double amplitude, double wavelength);
// z - curvature/2 * (x^2 + y^2): a bowl.
GroundPtr makeParabola(double curvature);
// z - slope * sqrt(x^2 + y^2): a cone (negative slope: a peak).
GroundPtr makeCone(double slope);
// z - amplitude * sin(2 pi x / wx) * sin(2 pi y / wy): bumps.
GroundPtr makeSinSinBumps(double amplitude, double wavelength_x, double wavelength_y);

}  // namespace groundsim
