// Warm one-step spheroid solve, sixteen pairs at a time (formulas in
// spheroid_warm_lanes.h and spheroid_contact.h). Compiled with
// -fno-math-errno -fno-trapping-math (CMakeLists.txt) so the loop, with its
// square roots, divisions and selects, runs as SIMD.
#include "virtual_triaxial/dem/spheroid_warm_lanes.h"

#include <cmath>

namespace vt::dem {

void SpheroidWarmLanes::repeat(int from, int to) {
  double* const fields[] = {dx, dy, dz, bi2, ki, bound_i, eix, eiy, eiz, bj2, kj, bound_j,
                            ejx, ejy, ejz, nx, ny, nz, mx, my, mz};
  for (double* f : fields) f[to] = f[from];
}

void solve_spheroid_warm_lanes(SpheroidWarmLanes& L, double step_tolerance) {
  const double tol2 = step_tolerance * step_tolerance;
  for (int k = 0; k < SpheroidWarmLanes::kLanes; ++k) {
    const double dx = L.dx[k], dy = L.dy[k], dz = L.dz[k];
    const double bi2 = L.bi2[k], ki = L.ki[k], eix = L.eix[k], eiy = L.eiy[k], eiz = L.eiz[k];
    const double bj2 = L.bj2[k], kj = L.kj[k], ejx = L.ejx[k], ejy = L.ejy[k], ejz = L.ejz[k];
    // start: (2 n_k - n_k-1)/|.| by one Newton step for 1/|v| (warm_start_normal)
    const double vx = 2.0 * L.nx[k] - L.mx[k], vy = 2.0 * L.ny[k] - L.my[k], vz = 2.0 * L.nz[k] - L.mz[k];
    const double v2 = vx * vx + vy * vy + vz * vz;
    const double start_unit = std::fabs(v2 - 1.0) <= 1e-6 ? 1.0 : 0.0;
    const double sv = 1.5 - 0.5 * v2;
    const double n0x = sv * vx, n0y = sv * vy, n0z = sv * vz;
    // support values at the start and the separation certificate
    const double ci = eix * n0x + eiy * n0y + eiz * n0z;
    const double cj = ejx * n0x + ejy * n0y + ejz * n0z;
    const double hi = std::sqrt(bi2 + ki * ci * ci);
    const double hj = std::sqrt(bj2 + kj * cj * cj);
    const double g = hi + hj - (n0x * dx + n0y * dy + n0z * dz);
    // tangent basis of n0 (branch on the sign only)
    const double sign = std::copysign(1.0, n0z);
    const double ta = -1.0 / (sign + n0z);
    const double tb = n0x * n0y * ta;
    const double t1x = 1.0 + sign * n0x * n0x * ta, t1y = sign * tb, t1z = -sign * n0x;
    const double t2x = tb, t2y = sign + n0y * n0y * ta, t2z = -n0y;
    // gradient and Hessian in (t1, t2)
    const double ihi = 1.0 / hi, ihj = 1.0 / hj;
    const double e1i = eix * t1x + eiy * t1y + eiz * t1z, e2i = eix * t2x + eiy * t2y + eiz * t2z;
    const double e1j = ejx * t1x + ejy * t1y + ejz * t1z, e2j = ejx * t2x + ejy * t2y + ejz * t2z;
    const double kci = ki * ci * ihi, kcj = kj * cj * ihj;
    const double ri = bi2 * ihi, rj = bj2 * ihj;
    const double qi = ri * ki * (ihi * ihi), qj = rj * kj * (ihj * ihj);
    const double g1 = kci * e1i + kcj * e1j - (t1x * dx + t1y * dy + t1z * dz);
    const double g2 = kci * e2i + kcj * e2j - (t2x * dx + t2y * dy + t2z * dz);
    const double h00 = (ri + qi * e1i * e1i) + (rj + qj * e1j * e1j) - g;
    const double h01 = qi * e1i * e2i + qj * e1j * e2j;
    const double h11 = (ri + qi * e2i * e2i) + (rj + qj * e2j * e2j) - g;
    const double det = h00 * h11 - h01 * h01;
    const double pd = (h00 > 0.0 ? 1.0 : 0.0) * (h11 > 0.0 ? 1.0 : 0.0) * (det > 0.0 ? 1.0 : 0.0);
    const double idet = 1.0 / det;
    const double s1 = (h01 * g2 - h11 * g1) * idet;
    const double s2 = (h01 * g1 - h00 * g2) * idet;
    const double done = s1 * s1 + s2 * s2 <= tol2 ? 1.0 : 0.0;  // 0 for NaN
    // the step, normalised by one Newton step for 1/|v|
    const double ux = n0x + s1 * t1x + s2 * t2x, uy = n0y + s1 * t1y + s2 * t2y, uz = n0z + s1 * t1z + s2 * t2z;
    const double u2 = ux * ux + uy * uy + uz * uz;
    const double step_unit = std::fabs(u2 - 1.0) <= 1e-6 ? 1.0 : 0.0;
    const double su = 1.5 - 0.5 * u2;
    const double nx = su * ux, ny = su * uy, nz = su * uz;
    // support points at n* by the series of h about n0
    const double c1i = eix * nx + eiy * ny + eiz * nz, c1j = ejx * nx + ejy * ny + ejz * nz;
    const double xi = ki * (c1i - ci) * (c1i + ci) * (ihi * ihi);
    const double xj = kj * (c1j - cj) * (c1j + cj) * (ihj * ihj);
    const double series = (std::fabs(xi) <= 1e-4 ? 1.0 : 0.0) * (std::fabs(xj) <= 1e-4 ? 1.0 : 0.0);
    const double h1i = hi * (1.0 + xi * (0.5 + xi * (-0.125 + xi * 0.0625)));
    const double h1j = hj * (1.0 + xj * (0.5 + xj * (-0.125 + xj * 0.0625)));
    const double ih1i = ihi * (1.0 + xi * (-0.5 + xi * (0.375 - xi * 0.3125)));
    const double ih1j = ihj * (1.0 + xj * (-0.5 + xj * (0.375 - xj * 0.3125)));
    const double kc1i = ki * c1i, kc1j = kj * c1j;
    const double pix = ih1i * (bi2 * nx + kc1i * eix), piy = ih1i * (bi2 * ny + kc1i * eiy),
                 piz = ih1i * (bi2 * nz + kc1i * eiz);
    const double pjx = ih1j * (bj2 * nx + kc1j * ejx), pjy = ih1j * (bj2 * ny + kc1j * ejy),
                 pjz = ih1j * (bj2 * nz + kc1j * ejz);
    const double delta = h1i + h1j - (nx * dx + ny * dy + nz * dz);
    // far-side check delta <= r_i + r_j - |d| (in squares) and bounding spheres
    const double reach = L.bound_i[k] + L.bound_j[k];
    const double d2 = dx * dx + dy * dy + dz * dz;
    const double rhs = reach + 1e-12 * reach - delta;
    const double near_side = (rhs >= 0.0 ? 1.0 : 0.0) * (d2 <= rhs * rhs ? 1.0 : 0.0) * (d2 < reach * reach ? 1.0 : 0.0);
    // flags as 0/1 doubles (bools of several widths keep the loop scalar)
    const double apart = g < 0.0 ? start_unit : 0.0;
    const double solved = start_unit * pd * done * step_unit * series * near_side;
    L.code[k] = apart > 0.0 ? 0.0 : (solved > 0.0 ? 1.0 : 2.0);
    L.gap[k] = -g;
    L.delta[k] = delta;
    L.ox[k] = nx; L.oy[k] = ny; L.oz[k] = nz;
    L.cx[k] = 0.5 * ((pix - pjx) + dx);
    L.cy[k] = 0.5 * ((piy - pjy) + dy);
    L.cz[k] = 0.5 * ((piz - pjz) + dz);
  }
}

}  // namespace vt::dem
