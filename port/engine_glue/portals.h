#pragma once
// Quake III portal surfaces in traced views: mirrors and misc_portal_camera windows. Surfaces
// whose shader has the `portal` keyword are drawn by the tracer as mirror materials; each frame
// the game's RT_PORTALSURFACE entities say, per plane, whether it is a mirror or a window to a
// camera elsewhere, and the plane goes to the renderer as a pa::PortalDesc (see scene_types.h).
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "port/engine_glue/ioq3_abi.h"
#include "renderer/scene/scene_types.h"

namespace q3 {
struct BspFile;
struct WorldScene;
}  // namespace q3
namespace pa {
class Renderer;
}

namespace glue {

/// A plane of the world holding portal surfaces (the engine's R_PlaneForSurface).
struct PortalPlane {
  glm::vec3 normal{0.0f, 0.0f, 1.0f};   ///< Unit; the portal is seen from this side.
  float dist = 0.0f;                   ///< dot(normal, p) = dist on the plane.
};

/// Distinct planes of the world model's portal surfaces: planar faces (the face plane, or the
/// plane of their first triangle when the file stores none) and triangle soups (the plane of
/// their first triangle); patches have no plane and are skipped.
/// `portalShader` flags the BSP shader lump entries whose shader is a portal.
std::vector<PortalPlane> findPortalPlanes(const q3::BspFile& bsp, const std::vector<bool>& portalShader);

/// Where rays entering `plane` come out this frame, as the engine decides it
/// (R_GetPortalOrientations + R_MirrorPoint): the first RT_PORTALSURFACE entity within 64 units
/// of the plane is a mirror when origin == oldorigin, else a camera at oldorigin looking along
/// axis[0] (rolled by skinNum degrees, or spun at `frame` degrees/s or swung +-4 degrees when
/// oldframe is set, at refdef time `timeMs`). nullopt without such an entity or with degenerate axes.
std::optional<pa::PortalDesc> portalFor(const PortalPlane& plane, std::span<const q3abi::refEntity_t> entities,
                                        int timeMs);

/// The map's portal planes and the portals last handed to the renderer.
class PortalViews {
 public:
  /// Finds the portal planes of a freshly built world (materials with `mirror` = portal shaders).
  void load(const q3::BspFile& bsp, const q3::WorldScene& scene);
  /// Forgets the map (and what the renderer was given).
  void clear();
  /// Gives the renderer this frame's portals, when they changed; call before commit().
  void update(std::span<const q3abi::refEntity_t> entities, int timeMs, pa::Renderer& renderer);
  /// The portal planes of the loaded map.
  const std::vector<PortalPlane>& planes() const { return planes_; }

 private:
  std::vector<PortalPlane> planes_;
  std::vector<pa::PortalDesc> current_;
  std::vector<pa::PortalDesc> candidate_;   ///< This frame's portals (kept: no allocation per frame).
};

}  // namespace glue
