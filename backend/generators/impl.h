// Internal: one function per generator, each building a `Generated` from the arguments
// or failing with `detail::fail` (see common.h). Dispatched by `generate`.
#pragma once

#include "backend/generators/common.h"

namespace nomec::backend::detail {

// rings.cpp
Generated make_funnel(const ArgReader& a);
Generated make_tunnel(const ArgReader& a);
Generated make_circle(const ArgReader& a);
Generated make_mobiusstrip(const ArgReader& a);
Generated make_rimribbon(const ArgReader& a);
// surfaces.cpp
Generated make_torus(const ArgReader& a);
Generated make_sphere(const ArgReader& a);
Generated make_ellipsoid(const ArgReader& a);
Generated make_cylinder(const ArgReader& a);
Generated make_hyperboloid(const ArgReader& a);
Generated make_dupin(const ArgReader& a);
Generated make_torusknot(const ArgReader& a);
// functions.cpp
Generated make_genparametricsurf(const ArgReader& a);
Generated make_gencartesiansurf(const ArgReader& a);
Generated make_genimplicitsurf(const ArgReader& a);
// curves.cpp
Generated make_helix(const ArgReader& a);
Generated make_spiral(const ArgReader& a);
Generated make_beziercurve(const ArgReader& a);
Generated make_bspline(const ArgReader& a);

}  // namespace nomec::backend::detail
