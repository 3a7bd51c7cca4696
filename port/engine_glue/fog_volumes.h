#pragma once
// The map's fog volumes (fogParms brushes) in the tracer: set with the world, taken away for
// views without the world (RDF_NOWORLDMODEL: HUD heads, menus) and put back after them.
#include <cstddef>

#include "port/scene_bridge/scene_bridge.h"
#include "renderer/scene/renderer.h"

namespace glue {

/// Which fog volumes the tracer holds.
class ViewFog {
 public:
  /// Keeps the map's fog volumes (WorldHandles::fog) and hands them to the renderer (shown).
  void load(pa::bridge::FogVolumes volumes, pa::Renderer& renderer);
  /// Shows the volumes for a view with the world, none for a view without it (no-op when unchanged).
  void show(bool withWorld, pa::Renderer& renderer);
  /// Number of volumes of the map.
  size_t size() const { return volumes_.volumes.size(); }

 private:
  pa::bridge::FogVolumes volumes_;
  bool shown_ = false;
};

}  // namespace glue
