// SLIDE's flat quadrics and its cyclide: disk, ring and cyclide (slide.md §3.5 names them;
// their fields and defaults were not retrievable, so both are nomec's, documented in
// docs/dialects.md and in each argument's hover text). θ runs from +x towards +y about the
// z axis, as for SLIDE's other quadrics (slide.md §4.1); flat shapes face +z.
#include <cmath>
#include <string>
#include <vector>

#include "backend/generators/impl.h"

namespace nomec::backend::detail {

// A disk: a centre vertex `center` at (0, 0, height) and rim vertices `v{i}` at
// θ_i = i·thetamax/thetaslices, radius `radius`; i = 0 … thetaslices − 1 around a full
// disk, 0 … thetaslices for a pie slice. One triangle (center, v_i, v_{i+1}) per slice,
// counter-clockwise seen from +z, so the disk faces +z and has one border: its rim (and, for
// a slice, the two radii).
Generated make_Disk(const ArgReader& a) {
  using A = ir::gen_arg::Disk;
  const double r = a.has(A::radius) ? a.positive(A::radius) : 1.0;
  const double z = a.number_or(A::height, 0.0);
  const double theta_max = a.number_or(A::theta_max, 360.0);
  const bool full = full_turn(theta_max, ir::arg_index(A::theta_max), a.name(A::theta_max));
  const int n = a.count_or(A::theta_segs, full ? 3 : 1, 16);
  check_size(n + 2LL, ir::arg_index(A::theta_segs));
  Generated g;
  const int32_t centre = g.soup.add_vertex({0.0, 0.0, z}, "center");
  const int rim = full ? n : n + 1;
  std::vector<int32_t> v;
  for (int i = 0; i < rim; ++i) {
    const double th = radians(i * theta_max / n);
    v.push_back(g.soup.add_vertex({r * std::cos(th), r * std::sin(th), z}, "v" + std::to_string(i)));
  }
  for (int i = 0; i < n; ++i) g.soup.add_face({centre, v[i], v[(i + 1) % rim]});
  return g;
}

// A ring (annulus): vertices `v{i}_0` on the inner circle and `v{i}_1` on the outer one at
// θ_i = i·thetamax/thetaslices, in the plane z = height; one quad per slice, facing +z.
// A full ring has two borders (χ = 0), a slice one (χ = 1). When only one radius is given
// the other is twice or half of it, so a file that gives either still gets a ring.
Generated make_Ring(const ArgReader& a) {
  using A = ir::gen_arg::Ring;
  const bool has_in = a.has(A::inner_radius), has_out = a.has(A::outer_radius);
  const double given_in = has_in ? a.positive(A::inner_radius) : 0.0;
  const double given_out = has_out ? a.positive(A::outer_radius) : 0.0;
  const double ri = has_in ? given_in : (has_out ? given_out / 2.0 : 0.5);
  const double ro = has_out ? given_out : (has_in ? 2.0 * given_in : 1.0);
  if (!(ro > ri)) fail(ir::arg_index(A::outer_radius), "`outerradius` must be greater than `innerradius`");
  const double z = a.number_or(A::height, 0.0);
  const double theta_max = a.number_or(A::theta_max, 360.0);
  const bool full = full_turn(theta_max, ir::arg_index(A::theta_max), a.name(A::theta_max));
  const int n = a.count_or(A::theta_segs, full ? 3 : 1, 16);
  check_size(2LL * (n + 1), ir::arg_index(A::theta_segs));
  Generated g;
  add_grid(
      g.soup, n, 1, full, false,
      [&](int i, int j) {
        const double th = radians(i * theta_max / n);
        const double r = j == 0 ? ri : ro;
        return glm::dvec3(r * std::cos(th), r * std::sin(th), z);
      },
      /*flip=*/true);
  return g;
}

// A ring Dupin cyclide with the torus's field names: the standard parametrisation (NOME3's
// `dupin`) with a = majorradius, d = minorradius, c = eccentricity and b = √(a² − c²), at
// u = θ and v = π − φ, so that vertex `v{i}_{j}` (θ_i = i·thetamax/thetaslices,
// φ_j = j·360°/phislices) lies where SLIDE's torus puts it when the eccentricity is 0:
// ((a + d cos φ) cos θ, (a + d cos φ) sin θ, −d sin φ). The tube's radius is d − c at +x and
// d + c at −x. A full turn is closed (genus 1, no hole as in NOME3's `dupin`); less is a tube
// open at both ends. Quads, facing out of the tube.
Generated make_Cyclide(const ArgReader& a) {
  using A = ir::gen_arg::Cyclide;
  const double ma = a.has(A::major_radius) ? a.positive(A::major_radius) : 1.0;
  const double d = a.has(A::minor_radius) ? a.positive(A::minor_radius) : ma / 4.0;
  const double c = a.number_or(A::eccentricity, d / 2.0);
  if (!(d < ma)) {
    fail(ir::arg_index(A::minor_radius), "`minorradius` must be smaller than `majorradius` (the tube would reach the "
                                         "axis and the cyclide intersect itself)");
  }
  if (!(std::abs(c) < d)) {
    fail(ir::arg_index(A::eccentricity), "`eccentricity` must be smaller than `minorradius` in absolute value (the tube "
                                         "would pinch to a point and the cyclide intersect itself)");
  }
  const double theta_max = a.number_or(A::theta_max, 360.0);
  const bool full = full_turn(theta_max, ir::arg_index(A::theta_max), a.name(A::theta_max));
  const int ts = a.count_or(A::theta_segs, full ? 3 : 1, 16);
  const int ps = a.count_or(A::phi_segs, 3, 8);
  check_size(static_cast<long long>(ts + 1) * ps, ir::arg_index(A::theta_segs));
  const double b = std::sqrt(ma * ma - c * c);
  Generated g;
  add_grid(
      g.soup, ts, ps, full, true,
      [&](int i, int j) { return dupin_point(ma, b, c, d, radians(i * theta_max / ts), kPi - 2.0 * kPi * j / ps); },
      /*flip=*/true);
  return g;
}

}  // namespace nomec::backend::detail
