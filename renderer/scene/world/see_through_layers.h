#pragma once
// The see-through layers a camera ray crosses (additive materials: glows, flames, smoke, marks):
// recorded as candidates while the ray is traversed, worked out once its closest hit is known.
#include <span>

#include "renderer/scene/world/render_scene.h"

namespace pa {

/// Adds an additive triangle the traversal met to hits.candidates; when all are taken, the
/// nearest are kept, ties broken by table (world first), instance, then the later primitive first
/// (AdditiveHits::drawnBefore's order), so the set kept does not depend on the order the
/// triangles were met in. A triangle reported twice is held twice and its layer
/// worked out once (resolveRayLayers, resolvePacketLayers).
void recordLayerCandidate(AdditiveHits& hits, const AdditiveHits::Candidate& candidate);

/// Works out the layers of one ray's candidates nearer than `tEnd` (its closest hit, or
/// infinity) into hits.entries, and empties the candidates; in display values where
/// hits.displayValues (the texture read as stored, times display-value vertex colours and factors).
void resolveRayLayers(const RenderScene& scene, AdditiveHits& hits, const Ray& ray, float tEnd);

/// resolveRayLayers for each ray of a packet traced by intersectCameraPacket, with the same
/// entries in the same order: the rays crossing one triangle are worked out together (its
/// corners, material and winding read once).
void resolvePacketLayers(const RenderScene& scene, std::span<TracedCameraRay> rays);

}  // namespace pa
