// atan, sin and tanh of four doubles at once. Where `wide` (see
// useWideSimd: an x86-64-v3 CPU, physics.deterministic off) they go through
// glibc's vector math library (libmvec, part of libc6: within 4 ulp of the
// exact value, so rounding-level against libm's scalar functions); otherwise
// each lane calls the scalar libm function, exactly as the code did before.
// `in` and `out` may be the same array.
#pragma once

namespace groundsim {

void atan4(const double* in, double* out, bool wide);
void sin4(const double* in, double* out, bool wide);
void tanh4(const double* in, double* out, bool wide);

// Whether the wide calls above really take the vector library (false where
// it is not linked: then they are the scalar loop).
bool vectorMathAvailable();

}  // namespace groundsim
