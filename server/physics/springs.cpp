// Report eqs. (1), (13), (14): tension S (|Xj - Xk| - R0) + D d/dt |Xj - Xk|
// along the line between the points. The dashpot acts on the rate of change
// of length (eq. 1); eq. 13's |Uj - Uk| would push points apart whatever
// their relative motion.
#include "forces.hpp"

namespace groundsim {

void applySprings(const Model& m, Workspace& ws) {
  for (auto& f : ws.f_spring) f.setZero();
  for (const Spring& s : m.springs) {
    const Vec3 d = ws.point_pos[s.b] - ws.point_pos[s.a];
    const Vec3 du = ws.point_vel[s.b] - ws.point_vel[s.a];
    Vec3 f;  // force on a; b gets -f
    if (s.isotropic) {
      f = s.stiffness * d + s.damping * du;
    } else {
      const double len = d.norm();
      if (len < 1e-12) continue;  // direction undefined; zero-length only for isotropic springs
      const Vec3 dir = d / len;
      const double tension = s.stiffness * (len - s.rest_length) + s.damping * du.dot(dir);
      f = tension * dir;
    }
    ws.f_spring[s.a] += f;
    ws.f_spring[s.b] -= f;
  }
}

}  // namespace groundsim
