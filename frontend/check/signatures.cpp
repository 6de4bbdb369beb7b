// Generator signature tables (see signatures.h). Argument meanings follow docs/generators.md
// and the NOME seed report; angles are in degrees.
#include "frontend/check/signatures.h"

namespace nomec {

using ast::BlockKind;

const GenSignature* signature_for(BlockKind kind, Dialect dialect) {
  static const GenSignature funnel_nome{{"n", "ro", "ratio", "h"}, {}, {"n"}};
  static const GenSignature funnel_nome3{{"radius", "ratio", "height", "n"}, {}, {"n"}};
  static const GenSignature tunnel{{"n", "ro", "ratio", "h"}, {"dri_low", "hgt_low"}, {"n"}};
  static const GenSignature circle{{"radius", "segs"}, {}, {"segs"}};
  static const GenSignature sphere{{"radius", "theta_max", "phi_min", "phi_max", "theta_segs", "phi_segs"}, {}, {"theta_segs", "phi_segs"}};
  static const GenSignature ellipsoid{{"a", "b", "theta_max", "phi_min", "phi_max", "theta_segs", "phi_segs"}, {}, {"theta_segs", "phi_segs"}};
  static const GenSignature cylinder{{"radius", "height", "theta_max", "theta_segs", "height_segs"}, {}, {"theta_segs", "height_segs"}};
  static const GenSignature hyperboloid{{"a", "b", "c", "height", "theta_segs", "height_segs"}, {}, {"theta_segs", "height_segs"}};
  static const GenSignature dupin{{"a", "b", "c", "d", "u_segs", "v_segs"}, {}, {"u_segs", "v_segs"}};
  static const GenSignature mobius{{"radius", "num_twists", "num_cuts", "n"}, {}, {"num_twists", "num_cuts", "n"}};
  static const GenSignature helix{{"radius", "height", "turns", "segs"}, {}, {"segs"}};
  static const GenSignature spiral{{"growth", "height", "turns", "segs"}, {}, {"segs"}};
  static const GenSignature torus{{"major_radius", "minor_radius", "theta_max", "phi_min", "phi_max", "theta_segs", "phi_segs"}, {}, {"theta_segs", "phi_segs"}};
  static const GenSignature torusknot{{"symm", "turns", "major_radius", "minor_radius", "tube_radius", "circ_segs", "sweep_segs"}, {}, {"symm", "turns", "circ_segs", "sweep_segs"}};
  static const GenSignature param_surf{{"u_min", "u_max", "v_min", "v_max", "u_segs", "v_segs"}, {}, {"u_segs", "v_segs"}};
  static const GenSignature cart_surf{{"x_min", "x_max", "y_min", "y_max", "x_segs", "y_segs"}, {}, {"x_segs", "y_segs"}};
  static const GenSignature impl_surf{{"x_min", "x_max", "y_min", "y_max", "z_min", "z_max", "resolution"}, {}, {"resolution"}};
  switch (kind) {
    case BlockKind::Funnel: return dialect == Dialect::Nome3 ? &funnel_nome3 : &funnel_nome;
    case BlockKind::Tunnel: return &tunnel;
    case BlockKind::Circle: return &circle;
    case BlockKind::Sphere: return &sphere;
    case BlockKind::Ellipsoid: return &ellipsoid;
    case BlockKind::Cylinder: return dialect == Dialect::Slide ? nullptr : &cylinder;
    case BlockKind::Hyperboloid: return &hyperboloid;
    case BlockKind::Dupin: return &dupin;
    case BlockKind::Mobiusstrip: return &mobius;
    case BlockKind::Helix: return &helix;
    case BlockKind::Spiral: return &spiral;
    case BlockKind::Torus: return &torus;
    case BlockKind::Torusknot: return &torusknot;
    case BlockKind::Genparametricsurf: return &param_surf;
    case BlockKind::Gencartesiansurf: return &cart_surf;
    case BlockKind::Genimplicitsurf: return &impl_surf;
    default: return nullptr;
  }
}

std::string_view argument_doc(BlockKind kind, std::string_view arg) {
  struct Doc {
    BlockKind kind;  // Bank = any generator
    std::string_view arg, doc;
  };
  static const Doc docs[] = {
      {BlockKind::Funnel, "n", "number of sides: quads around the funnel (count, ≥ 3)"},
      {BlockKind::Funnel, "ro", "radius of the base ring (at z = 0)"},
      {BlockKind::Funnel, "ratio", "the top ring's radius is ro·(1 + ratio)"},
      {BlockKind::Funnel, "h", "height of the top ring"},
      {BlockKind::Funnel, "radius", "radius of the base ring (at z = 0)"},
      {BlockKind::Funnel, "height", "height of the top ring"},
      {BlockKind::Tunnel, "n", "number of sides of each ring (count, ≥ 3)"},
      {BlockKind::Tunnel, "ro", "radius of the middle ring (at z = 0)"},
      {BlockKind::Tunnel, "ratio", "the outer rings' radius is ro·(1 + ratio)"},
      {BlockKind::Tunnel, "h", "height of the upper ring (the lower one is at −h)"},
      {BlockKind::Tunnel, "dri_low", "ratio of the lower ring, if it differs (asymmetric tunnel)"},
      {BlockKind::Tunnel, "hgt_low", "depth of the lower ring, if it differs (asymmetric tunnel)"},
      {BlockKind::Torus, "major_radius", "distance from the centre to the middle of the tube"},
      {BlockKind::Torus, "minor_radius", "radius of the tube"},
      {BlockKind::Torusknot, "symm", "symmetry: how many times the knot winds around the axis (count)"},
      {BlockKind::Torusknot, "turns", "how many times the knot winds through the hole (count)"},
      {BlockKind::Torusknot, "major_radius", "radius of the torus the knot lies on"},
      {BlockKind::Torusknot, "minor_radius", "radius of the torus's tube the knot winds around"},
      {BlockKind::Torusknot, "tube_radius", "radius of the tube swept along the knot"},
      {BlockKind::Torusknot, "circ_segs", "segments around the swept tube (count)"},
      {BlockKind::Torusknot, "sweep_segs", "segments along the knot (count)"},
      {BlockKind::Mobiusstrip, "radius", "radius of the strip's centre circle"},
      {BlockKind::Mobiusstrip, "num_twists", "number of half twists (count)"},
      {BlockKind::Mobiusstrip, "num_cuts", "number of lengthwise cuts (count; only 0 is built today)"},
      {BlockKind::Mobiusstrip, "n", "segments around the strip (count)"},
      {BlockKind::Helix, "turns", "number of turns"},
      {BlockKind::Helix, "height", "height climbed over all turns"},
      {BlockKind::Spiral, "growth", "how fast the radius grows per turn"},
      {BlockKind::Spiral, "height", "height climbed over all turns"},
      {BlockKind::Spiral, "turns", "number of turns"},
      {BlockKind::Ellipsoid, "a", "semi-axis along x"},
      {BlockKind::Ellipsoid, "b", "semi-axis along z"},
      {BlockKind::Hyperboloid, "a", "waist radius along x"},
      {BlockKind::Hyperboloid, "b", "waist radius along y"},
      {BlockKind::Hyperboloid, "c", "how fast the surface widens with height"},
      {BlockKind::Dupin, "a", "Dupin cyclide parameter a (size of the ring)"},
      {BlockKind::Dupin, "b", "Dupin cyclide parameter b"},
      {BlockKind::Dupin, "c", "Dupin cyclide parameter c (eccentricity)"},
      {BlockKind::Dupin, "d", "Dupin cyclide parameter d (tube size)"},
      {BlockKind::Bank, "radius", "radius"},
      {BlockKind::Bank, "height", "height"},
      {BlockKind::Bank, "segs", "number of segments (count)"},
      {BlockKind::Bank, "theta_max", "sweep angle around the axis, in degrees (360 = closed)"},
      {BlockKind::Bank, "phi_min", "start angle from the pole, in degrees"},
      {BlockKind::Bank, "phi_max", "end angle from the pole, in degrees"},
      {BlockKind::Bank, "theta_segs", "segments around the axis (count)"},
      {BlockKind::Bank, "phi_segs", "segments from pole to pole (count)"},
      {BlockKind::Bank, "height_segs", "segments along the height (count)"},
      {BlockKind::Bank, "u_min", "start of the u parameter range"},
      {BlockKind::Bank, "u_max", "end of the u parameter range"},
      {BlockKind::Bank, "v_min", "start of the v parameter range"},
      {BlockKind::Bank, "v_max", "end of the v parameter range"},
      {BlockKind::Bank, "u_segs", "segments along u (count)"},
      {BlockKind::Bank, "v_segs", "segments along v (count)"},
      {BlockKind::Bank, "x_min", "start of the x range"},
      {BlockKind::Bank, "x_max", "end of the x range"},
      {BlockKind::Bank, "y_min", "start of the y range"},
      {BlockKind::Bank, "y_max", "end of the y range"},
      {BlockKind::Bank, "z_min", "start of the z range"},
      {BlockKind::Bank, "z_max", "end of the z range"},
      {BlockKind::Bank, "x_segs", "segments along x (count)"},
      {BlockKind::Bank, "y_segs", "segments along y (count)"},
      {BlockKind::Bank, "resolution", "grid cells per axis for the implicit surface (count)"},
  };
  for (const Doc& d : docs) {
    if (d.kind == kind && d.arg == arg) return d.doc;
  }
  for (const Doc& d : docs) {
    if (d.kind == BlockKind::Bank && d.arg == arg) return d.doc;
  }
  return {};
}

}  // namespace nomec
