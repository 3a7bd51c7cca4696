#pragma once
// What scene edits changed that camera rays see directly, so that accumulation over a still view
// (RenderSettings::accumulate) restarts only the pixels that show a change. Lighting edits (lights
// added, moved, dimmed) are not in it: an accumulated picture averages them over time, as a long
// exposure does.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "renderer/scene/scene_types.h"

namespace pa {

/// Edits since a point in time, by what camera rays see of them.
struct SeenChanges {
  /// An edit that may change any pixel (a texture replaced, fog volumes changed, a mesh
  /// removed): accumulation starts again everywhere.
  bool everything = false;
  bool sky = false;                  ///< The sky (what rays that leave the scene see) changed.
  bool portals = false;              ///< The portals (where views through them come from) changed.
  std::vector<uint8_t> instances;    ///< By InstanceId: 1 = added, removed, moved, re-meshed or re-tinted.
  std::vector<uint8_t> materials;    ///< By MaterialId: 1 = replaced by a different material.
  bool anyObject = false;            ///< Some entry of instances or materials is set.

  /// True when nothing is recorded.
  bool empty() const { return !everything && !sky && !portals && !anyObject; }
  /// Forgets every edit, keeping the memory.
  void clear() {
    everything = sky = portals = anyObject = false;
    std::fill(instances.begin(), instances.end(), uint8_t{0});
    std::fill(materials.begin(), materials.end(), uint8_t{0});
  }
  /// Records an edit of instance id.
  void markInstance(InstanceId id) { mark(instances, id); }
  /// Records an edit of material id.
  void markMaterial(MaterialId id) { mark(materials, id); }
  /// Adds other's edits to these.
  void merge(const SeenChanges& other) {
    everything = everything || other.everything;
    sky = sky || other.sky;
    portals = portals || other.portals;
    for (size_t i = 0; i < other.instances.size(); ++i)
      if (other.instances[i]) markInstance(static_cast<InstanceId>(i));
    for (size_t i = 0; i < other.materials.size(); ++i)
      if (other.materials[i]) markMaterial(static_cast<MaterialId>(i));
  }
  /// True when material id itself was replaced by a different material (a texture animation
  /// step, say); `everything` is not consulted.
  bool materialEdited(MaterialId id) const { return id != kNoId && flagged(materials, id); }
  /// True when a camera sample whose first visible hit was (instance, material) shows an edit.
  /// instance kNoId is the sky or a view through a portal: it shows sky edits, and portal and
  /// object edits when the scene has portals.
  bool seenAt(InstanceId instance, MaterialId material, bool scenePortals) const {
    if (everything) return true;
    if (instance == kNoId) return sky || portals || (scenePortals && anyObject);
    return flagged(instances, instance) || (material != kNoId && flagged(materials, material));
  }

 private:
  static bool flagged(const std::vector<uint8_t>& flags, uint32_t id) { return id < flags.size() && flags[id] != 0; }
  void mark(std::vector<uint8_t>& flags, uint32_t id) {
    if (id >= flags.size()) flags.resize(size_t{id} + 1, 0);   // grows with the scene, not per frame
    flags[id] = 1;
    anyObject = true;
  }
};

}  // namespace pa
