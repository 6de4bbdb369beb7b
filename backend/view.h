// The viewing set-up of a scene for a live preview (the language server's `nome/preview`,
// `nomec view`): the camera a SLIDE `render` looks through, placed by the instances along its
// path (`render vp gCam.iCam.cam world` with `instance cam id iCam translate (0 0 1)` puts it
// at (0, 0, 1) looking down −z), the render's lights with their colours and world positions
// and directions, and the background colour of the render's window (or JIPCAD's
// `backgroundcolor`). A file without `render` (NOME3) uses its first camera instance and
// every light instance. Plain data, JSON-free: lsp/ encodes it. Values are read with the
// module's current slider values.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "ir/ir.h"

namespace nomec::backend {

using Vec3 = std::array<double, 3>;

struct ViewCamera {
  std::string name;
  Vec3 position{0, 0, 0};
  Vec3 direction{0, 0, -1};  // where it looks (unit)
  Vec3 up{0, 1, 0};          // unit
  ir::Projection projection = ir::Projection::Parallel;
  /// The view volume in the camera's frame, SLIDE's order: xmin ymin zmin xmax ymax zmax
  /// (z negative in front of the camera).
  std::array<double, 6> frustum = ir::kDefaultFrustum;
};

struct ViewLight {
  std::string name;
  ir::LightType type = ir::kDefaultLightType;
  Vec3 color = ir::kDefaultLightColor;  // each in [0, 1]
  Vec3 position{0, 0, 0};
  Vec3 direction{0, 0, -1};  // where the light shines (unit): the light's −z
  bool on = true;
};

struct SceneView {
  std::optional<ViewCamera> camera;
  std::vector<ViewLight> lights;
  std::optional<Vec3> background;  // each in [0, 1]
  bool empty() const { return !camera && lights.empty() && !background; }
};

/// The viewing set-up of `module` (empty when the scene has none).
SceneView scene_view(const ir::Module& module);

}  // namespace nomec::backend
