#include "physics/kernels/fast_car.hpp"

#include <algorithm>
#include <cmath>

#include "physics/kernels/fast_car_kernel.hpp"

namespace groundsim {

namespace {
// the step keeps the wheels' controls on the stack: a scene of more (five
// cars and up) takes the general loop instead of throwing at construction
constexpr int kMaxWheels = 16;
}  // namespace

const char* rigidStepUnsupported(const Model& m) {
  if (m.opt.integrator != IntegratorKind::SemiImplicitEuler) return "integrator is not semi_implicit_euler";
  if (m.opt.contact.friction_model != FrictionModel::StickSlip) return "friction is not stick_slip";
  if (!m.particles.empty()) return "the model has particles";
  for (const SceneObject& o : m.objects)
    if (o.body >= 0) return "the scene has objects with mass";
  if (!m.road_cars.empty() || m.aux_states != 0) return "the model has road cars";
  return nullptr;
}

const char* fastCarUnsupported(const Model& m) {
  Vec3 n;
  double offset;
  if (const char* why = rigidStepUnsupported(m)) return why;
  for (int k : m.contact_points)
    if (m.points[k].body < 0) return "the model has particle contacts";
  if (!m.spring_fans.empty()) return "the model has spring fans (rim springs)";
  if (m.wheels.empty()) return "the model has no wheels";
  if (m.wheels.size() > static_cast<size_t>(kMaxWheels)) return "more than 16 wheels";
  for (const Wheel& w : m.wheels)
    if (w.contact != WheelContact::Circle) return "a wheel is not a circle";
  if (!m.ground || !m.ground->asPlane(&n, &offset)) return "the ground is not a plane";
  for (const Spring& s : m.springs)
    if (m.points[s.a].body < 0 || m.points[s.b].body < 0) return "a spring is not between body points";
  return nullptr;
}

namespace {

// Off-diagonal terms below 1e-14 of the largest diagonal one are the
// round-off of summing a body's point masses about its principal axes (a
// wheel's come out near 4e-16 of 20): they are dropped, so such a body
// takes the diagonal or symmetric product. That moves a result by far less
// than the round-off of one step.
void classifyInertia(FastCarPlan::BodyC& bc) {
  double* B = bc.Ib;
  const double scale = std::max({std::abs(B[0]), std::abs(B[4]), std::abs(B[8])});
  bc.diagonal = true;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c && !(std::abs(B[3 * r + c]) <= 1e-14 * scale)) bc.diagonal = false;
  bc.axis = -1;
  if (!bc.diagonal) return;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c) B[3 * r + c] = 0.0;
  // symmetric about axis k: the other two diagonal terms are equal
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    if (B[4 * i] != B[4 * j]) continue;
    bc.axis = k;
    bc.iso = B[4 * i];
    bc.along = B[4 * k] - B[4 * i];
    return;
  }
}

}  // namespace

FastCarPlan::BodyC bodyConstants(const Body& b) {
  FastCarPlan::BodyC bc{};
  // unclassified: a general matrix, which every reader handles; the fast
  // car's plan classifies (classifyInertia) where it reads the shape
  bc.diagonal = false;
  bc.axis = -1;
  bc.mass = b.mass;
  bc.inv_mass = 1.0 / b.mass;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) bc.Ib[3 * r + c] = b.inv_inertia(r, c);
  return bc;
}

FastCarPlan makeFastCarPlan(const Model& m) {
  FastCarPlan P;
  std::vector<int> used(m.points.size(), 0), index(m.points.size(), -1);
  for (const Spring& s : m.springs) used[s.a] = used[s.b] = 1;
  for (int k : m.contact_points) used[k] = 1;
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    FastCarPlan::BodyC bc = bodyConstants(m.bodies[i]);
    classifyInertia(bc);
    bc.first_point = static_cast<int>(P.pts.size());
    for (int k = m.body_point_begin[i]; k < m.body_point_end[i]; ++k) {
      if (!used[k]) continue;
      const Point& pt = m.points[k];
      FastCarPlan::PointC pc{};
      pc.body = static_cast<int>(i);
      pc.model_point = k;
      pc.lx = pt.local.x();
      pc.ly = pt.local.y();
      pc.lz = pt.local.z();
      pc.steer_wheel = pt.steer_wheel;
      pc.pivx = pt.steer_pivot.x();
      pc.pivy = pt.steer_pivot.y();
      pc.dx = (pt.local - pt.steer_pivot).x();
      pc.dy = (pt.local - pt.steer_pivot).y();
      index[k] = static_cast<int>(P.pts.size());
      P.pts.push_back(pc);
    }
    bc.end_point = static_cast<int>(P.pts.size());
    P.bodies.push_back(bc);
  }
  for (const Spring& s : m.springs)
    P.springs.push_back({index[s.a], index[s.b], s.stiffness, s.damping, s.rest_length, s.isotropic});
  for (const Wheel& w : m.wheels)
    P.wheels.push_back({w.body, w.carrier, w.axis.x(), w.axis.y(), w.axis.z(), w.radius});
  for (size_t k = 0; k < P.pts.size(); ++k)
    if (m.points[P.pts[k].model_point].contact)
      P.contacts.push_back({P.pts[k].body, static_cast<int>(k), m.points[P.pts[k].model_point].wheel});
  P.point_contacts = static_cast<int>(P.contacts.size());
  for (size_t w = 0; w < m.wheels.size(); ++w) P.contacts.push_back({m.wheels[w].body, -1, static_cast<int>(w)});
  Vec3 n;
  double offset = 0.0;
  m.ground->asPlane(&n, &offset);
  for (int k = 0; k < 3; ++k) P.n[k] = n[k];
  P.offset = offset;
  P.gn = n.norm();
  P.inv_gn = 1.0 / P.gn;
  const Vec3 cn = n / P.gn, t1 = cn.unitOrthogonal(), t2 = cn.cross(t1);
  for (int k = 0; k < 3; ++k) {
    P.t1[k] = t1[k];
    P.t2[k] = t2[k];
    P.gravity[k] = m.opt.gravity[k];
  }
  P.stiffness = m.opt.contact.stiffness;
  P.damping = m.opt.contact.damping;
  P.hunt_crossley = m.opt.contact.damping_model == NormalDamping::HuntCrossley;
  P.mu = m.ground->friction(Vec3::Zero(), m.opt.contact.friction);
  P.friction_iterations = m.opt.contact.friction_iterations;
  return P;
}

namespace {

using fastcar::Scratch;

GROUNDSIM_INLINE_BODY void evaluateBody(const FastCarPlan& P, const double* y, const double* drive,
                                        const double* brake, const double* steer, double h, Scratch<double>& S) {
  fastcar::kinematics(P, y, steer, S);
  fastcar::forces(P, y, drive, S);
  fastcar::frictionAndBrakes(P, y, brake, h, S);
}
GROUNDSIM_WIDE void evaluateWide(const FastCarPlan& P, const double* y, const double* drive,
                                 const double* brake, const double* steer, double h, Scratch<double>& S) {
  evaluateBody(P, y, drive, brake, steer, h, S);
}
void evaluateGeneric(const FastCarPlan& P, const double* y, const double* drive, const double* brake,
                     const double* steer, double h, Scratch<double>& S) {
  evaluateBody(P, y, drive, brake, steer, h, S);
}
GROUNDSIM_WIDE void integrateWide(const FastCarPlan& P, double* y, double h, Scratch<double>& S) {
  fastcar::integrate(P, y, h, S);
}
void integrateGeneric(const FastCarPlan& P, double* y, double h, Scratch<double>& S) {
  fastcar::integrate(P, y, h, S);
}

Mat3 mat(const double* R) {
  Mat3 M;
  M << R[0], R[1], R[2], R[3], R[4], R[5], R[6], R[7], R[8];
  return M;
}

// The workspace as computeForces leaves it for this model.
void exportEvaluation(const Model& m, const FastCarPlan& P, const double* y, double h, const Scratch<double>& S,
                      Workspace& ws) {
  for (size_t i = 0; i < P.bodies.size(); ++i) {
    const fastcar::BodyL<double>& B = S.bodies[i];
    ws.R[i] = mat(B.R);
    const FastCarPlan::BodyC& bc = P.bodies[i];
    if (bc.axis >= 0) {  // the kernel works with the world axis, not the matrix
      const Vec3 c(B.c[0], B.c[1], B.c[2]);
      ws.inv_inertia_world[i] = bc.iso * Mat3::Identity() + bc.along * c * c.transpose();
    } else {
      ws.inv_inertia_world[i] = mat(B.Iw);
    }
    ws.omega[i] = Vec3(B.w[0], B.w[1], B.w[2]);
    ws.com[i] = Vec3(y[13 * i], y[13 * i + 1], y[13 * i + 2]);
    ws.vel[i] = Vec3(y[13 * i + 7], y[13 * i + 8], y[13 * i + 9]);
    ws.body_force[i] = Vec3(B.F[0], B.F[1], B.F[2]);
    ws.body_torque[i] = Vec3(B.T[0], B.T[1], B.T[2]);
    const Body& b = m.bodies[i];
    const double H = P.n[0] * y[13 * i] + P.n[1] * y[13 * i + 1] + P.n[2] * y[13 * i + 2] - P.offset;
    ws.body_far[i] = !b.has_contact_points || (m.opt.broad_phase && H > b.bound_radius * 1.000001);
  }
  for (size_t k = 0; k < P.pts.size(); ++k) {
    const int q = P.pts[k].model_point;
    const fastcar::PointL<double>& pt = S.pts[k];
    ws.px[q] = pt.p[0];
    ws.py[q] = pt.p[1];
    ws.pz[q] = pt.p[2];
    ws.ux[q] = pt.u[0];
    ws.uy[q] = pt.u[1];
    ws.uz[q] = pt.u[2];
    ws.fx[q] = pt.f[0];
    ws.fy[q] = pt.f[1];
    ws.fz[q] = pt.f[2];
  }
  ws.ncontacts = 0;
  ws.max_depth = 0.0;
  ws.ground_energy = 0.0;
  const Vec3 n = Vec3(P.n[0], P.n[1], P.n[2]) / P.gn;
  const Vec3 t1(P.t1[0], P.t1[1], P.t1[2]), t2(P.t2[0], P.t2[1], P.t2[2]);
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    ws.wheel_normal[w] = 0.0;
    ws.wheel_friction[w] = 0.0;
    ws.wheel_slip[w] = 0.0;
    ws.brake_impulse[w] = S.con[P.point_contacts + w].bi;
  }
  for (size_t slot = 0; slot < P.contacts.size(); ++slot) {
    const fastcar::ContactL<double>& c = S.con[slot];
    const FastCarPlan::ContactC& cc = P.contacts[slot];
    if (!c.in) continue;
    Contact& k = ws.contacts[ws.ncontacts++];
    k.point = cc.pt >= 0 ? P.pts[cc.pt].model_point : -1;
    k.body = cc.body;
    k.particle = -1;
    k.wheel = cc.wheel;
    const size_t w = static_cast<size_t>(std::max(cc.wheel, 0));
    k.p = Vec3(c.p[0], c.p[1], c.p[2]);
    k.n = n;
    k.r = Vec3(c.rr[0], c.rr[1], c.rr[2]);
    k.depth = c.depth;
    k.normal = c.N;
    k.mu = P.mu;
    k.u = Vec3(c.u[0], c.u[1], c.u[2]);
    k.slip = k.u - k.u.dot(k.n) * k.n;
    k.t1 = t1;
    k.t2 = t2;
    k.a1 = Vec3(c.a1[0], c.a1[1], c.a1[2]);
    k.a2 = Vec3(c.a2[0], c.a2[1], c.a2[2]);
    k.b1 = Vec3(c.b1[0], c.b1[1], c.b1[2]);
    k.b2 = Vec3(c.b2[0], c.b2[1], c.b2[2]);
    k.k << c.k00, c.k01, c.k01, c.k11;
    k.k_inv << c.i00, c.i01, c.i10, c.i11;
    k.impulse = Eigen::Vector2d(c.j0, c.j1);
    k.friction = (c.j0 * t1 + c.j1 * t2) / h;
    ws.max_depth = std::max(ws.max_depth, k.depth);
    ws.ground_energy += 0.5 * P.stiffness * k.depth * k.depth;
    if (cc.wheel < 0) continue;
    ws.wheel_normal[w] += k.normal;
    ws.wheel_slip[w] = std::max(ws.wheel_slip[w], k.slip.norm());
    ws.wheel_friction[w] += k.friction.norm();
  }
  ws.drive_power = S.drive_power;
  ws.friction_sweeps = S.sweeps;
}

}  // namespace

struct FastCar::Impl {
  explicit Impl(const Model& m) : plan(makeFastCarPlan(m)), scratch(plan), y_eval(m.stateSize(), 0.0) {}
  FastCarPlan plan;
  Scratch<double> scratch;
  std::vector<double> y_eval;  // the configuration of the last evaluation
  double h = 0.0;              // and its step
};

FastCar::FastCar(const Model& m) : impl_(std::make_unique<Impl>(m)) {
  if (m.wheels.size() > static_cast<size_t>(kMaxWheels)) throw std::invalid_argument("fast car: too many wheels");
}
FastCar::~FastCar() = default;

bool FastCar::step(const Model& m, State& s, Workspace& ws) {
  const FastCarPlan& P = impl_->plan;
  Scratch<double>& S = impl_->scratch;
  double drive[kMaxWheels], brake[kMaxWheels], steer[kMaxWheels];
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    drive[w] = s.applied[w].drive_torque;
    brake[w] = s.applied[w].brake_torque;
    steer[w] = s.applied[w].steer;
  }
  const int n = std::max(1, m.opt.substeps);
  const double h = m.opt.dt / n;
  const bool wide = useWideSimd(m.opt.deterministic);
  double* y = s.y.data();
  for (int k = 0; k < n; ++k) {
    if (wide) evaluateWide(P, y, drive, brake, steer, h, S);
    else evaluateGeneric(P, y, drive, brake, steer, h, S);
    if (k + 1 == n) std::copy(y, y + s.y.size(), impl_->y_eval.begin());
    s.drive_work += h * S.drive_power;
    if (wide) integrateWide(P, y, h, S);
    else integrateGeneric(P, y, h, S);
  }
  impl_->h = h;
  double depth = 0.0;  // as detectGroundContacts leaves it
  for (const fastcar::ContactL<double>& c : S.con)
    if (c.in) depth = std::max(depth, c.depth);
  ws.max_depth = depth;
  // what checkHealth tests first, without its branches and messages: x - x
  // is 0 for a finite x and NaN otherwise, so one sum finds any NaN or
  // infinity; the speed bound is squared and kept a margin inside, so a
  // speed at the limit goes to checkHealth and its exact test
  double bad[4] = {0.0, 0.0, 0.0, 0.0}, v2 = 0.0;  // four chains, not one
  const size_t ny = s.y.size();
  size_t i = 0;
  for (; i + 4 <= ny; i += 4)
    for (int j = 0; j < 4; ++j) bad[j] += y[i + j] - y[i + j];
  for (; i < ny; ++i) bad[0] += y[i] - y[i];
  for (size_t b = 0; b < P.bodies.size(); ++b) {
    const double* yb = y + 13 * b;
    v2 = std::max(v2, yb[7] * yb[7] + yb[8] * yb[8] + yb[9] * yb[9]);
  }
  const Limits& lim = m.opt.limits;
  return (bad[0] + bad[1]) + (bad[2] + bad[3]) == 0.0 && depth <= lim.max_penetration &&
         v2 <= 0.99 * lim.max_speed * lim.max_speed;
}

void FastCar::exportTo(const Model& m, Workspace& ws) const {
  exportEvaluation(m, impl_->plan, impl_->y_eval.data(), impl_->h, impl_->scratch, ws);
}

}  // namespace groundsim
