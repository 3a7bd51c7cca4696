#include "renderer/scene/world/render_scene.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <span>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x2.hpp>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "renderer/core/srgb.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/world/see_through_layers.h"

namespace pa {

namespace {

/// What the HitFilter callback sees: the scene, the instance table traced, the ray and options.
struct FilterContext {
  const RenderScene* scene;
  bool overlay;
  const Ray* ray;
  const TraceRequest* request;
};

glm::vec3 toWorld(const glm::mat4x3& m, const glm::vec3& p) { return m * glm::vec4(p, 1.0f); }

/// v / d: one division of three lanes instead of three (each lane is divided as alone).
glm::vec3 divided(const glm::vec3& v, float d) {
#if defined(__SSE2__)
  alignas(16) float q[4];
  _mm_store_ps(q, _mm_div_ps(_mm_setr_ps(v.x, v.y, v.z, 0.0f), _mm_set1_ps(d)));
  return {q[0], q[1], q[2]};
#else
  return v / d;
#endif
}

/// A triangle's area in mesh uvs through an affine transform's linear part (0 without uvs).
float triangleUvArea(const MeshGeometry& g, uint32_t i0, uint32_t i1, uint32_t i2, const glm::mat3x2& transform) {
  if (g.uvs.empty()) return 0.0f;
  const glm::mat2 linear(transform[0], transform[1]);
  const glm::vec2 d1 = linear * (g.uvs[i1] - g.uvs[i0]);
  const glm::vec2 d2 = linear * (g.uvs[i2] - g.uvs[i0]);
  return 0.5f * std::abs(d1.x * d2.y - d1.y * d2.x);
}

/// The mip level of `texture` for a ray cone's footprint on a triangle of `uvArea` in its uvs
/// and `worldArea` in the world (0 where any of the three is not positive).
float mipLevel(const Texture& texture, float footprint, float uvArea, float worldArea) {
  if (!(footprint > 0.0f && uvArea > 0.0f && worldArea > 0.0f)) return 0.0f;
  const float texels = static_cast<float>(texture.width()) * static_cast<float>(texture.height());
  return std::log2(footprint * std::sqrt(uvArea * texels / worldArea));
}

bool acceptCandidate(const void* opaque, uint32_t instanceIndex, uint32_t prim, float u, float v, float t) {
  const auto& ctx = *static_cast<const FilterContext*>(opaque);
  const auto& instances = ctx.scene->instancesOf(ctx.overlay);
  if (instanceIndex >= instances.size()) return true;
  const RenderInstance& inst = instances[instanceIndex];
  if (prim >= inst.mesh->geometry.triangleCount()) return true;
  const MaterialRecord& record = ctx.scene->materialOf(inst, prim);
  const FilterRule rule = record.filter[static_cast<size_t>(ctx.request->kind)];
  switch (rule.action) {
    case FilterAction::Additive:
      // Worked out once the closest hit is known (see_through_layers.h): only those in front show.
      if (ctx.request->additive != nullptr)
        recordLayerCandidate(*ctx.request->additive, {t, instanceIndex, prim, u, v, ctx.overlay});
      return false;
    case FilterAction::Reject: return false;
    case FilterAction::Sky: return !(ctx.request->kind == RayKind::Shadow && ctx.request->towardEnvironment);
    case FilterAction::Accept:
    case FilterAction::Mask:
    case FilterAction::Blend: break;
  }
  if (rule.cullBack && glm::dot(ctx.scene->windingNormal(inst, prim), ctx.ray->dir) > 0.0f) return false;
  const MaterialDesc& m = record.desc;
  switch (rule.action) {
    case FilterAction::Mask: {
      const float alpha = ctx.scene->coverageAt(inst, prim, {u, v});
      return m.alphaInvert ? alpha < m.alphaCutoff : alpha >= m.alphaCutoff;
    }
    case FilterAction::Blend: {
      const float coverage = std::clamp(ctx.scene->coverageAt(inst, prim, {u, v}) * m.opacity, 0.0f, 1.0f);
      const uint32_t bits = sampling::hashCombine(sampling::hashCombine(ctx.request->randomBits, instanceIndex), prim);
      return sampling::toUnitFloat(bits) < coverage;
    }
    default: return true;
  }
}

/// The face of one-sided triangles a kind of ray skips, as acceptCandidate would: shadow rays
/// take both faces, camera and bounce rays not the back one.
FaceCull faceCullFor(RayKind kind) { return kind == RayKind::Shadow ? FaceCull::None : FaceCull::Back; }

uint32_t rayMaskFor(RayKind kind) {
  switch (kind) {
    case RayKind::Camera: return kMaskCamera;
    case RayKind::Bounce: return kMaskBounce;
    case RayKind::Shadow: return kMaskShadow;
  }
  return kMaskAll;
}

}  // namespace

FilterRule materialFilterRule(const MaterialDesc& m, RayKind kind) {
  if (m.sky) return {FilterAction::Sky, false};
  if (kind == RayKind::Shadow) {
    if (!m.castsShadows || m.alphaMode == AlphaMode::Additive) return {FilterAction::Reject, false};
  } else if (!m.visible) {
    return {FilterAction::Reject, false};
  }
  if (m.alphaMode == AlphaMode::Opaque && (m.twoSided || kind == RayKind::Shadow)) return {FilterAction::Accept, false};
  const bool cullBack = !m.twoSided && kind != RayKind::Shadow && m.alphaMode != AlphaMode::Additive;
  switch (m.alphaMode) {
    case AlphaMode::Mask: return {FilterAction::Mask, cullBack};
    case AlphaMode::Blend: return {FilterAction::Blend, cullBack};
    case AlphaMode::Additive: return {FilterAction::Additive, false};
    case AlphaMode::Opaque: break;
  }
  return {FilterAction::Accept, cullBack};
}

HitRule materialHitRule(const MaterialDesc& m) {
  if (m.alphaMode != AlphaMode::Opaque || !m.castsShadows || !m.visible || m.sky) return HitRule::Filtered;
  return m.twoSided ? HitRule::Opaque : HitRule::OneSided;
}

glm::vec3 AdditiveHits::transmitBefore(float t) const {
  glm::vec3 product(1.0f);
  for (uint32_t i = 0; i < count; ++i) {
    if (entries[i].t < t) product *= entries[i].transmit;
  }
  return product;
}

glm::vec3 AdditiveHits::sumBefore(float t) const {
  glm::vec3 sum(0.0f);
  for (uint32_t i = 0; i < count; ++i) {
    if (entries[i].t < t) sum += entries[i].color;
  }
  return sum;
}

bool RenderScene::intersect(Ray& ray, Hit& hit, const TraceRequest& request) const {
  const auto& instances = instancesOf(request.overlay);
  if (instances.empty()) return false;
  const FilterContext ctx{this, request.overlay, &ray, &request};
  const HitFilter filter{&acceptCandidate, &ctx, faceCullFor(request.kind)};
  const Tlas& tlas = request.overlay ? overlayTlas : worldTlas;
  const bool found = tlas.intersect(ray, hit, rayMaskFor(request.kind), filter);
  if (request.additive != nullptr && request.additive->candidateCount != 0)
    resolveRayLayers(*this, *request.additive, ray, found ? hit.t : std::numeric_limits<float>::infinity());
  return found;
}

void RenderScene::intersectCameraPacket(std::span<TracedCameraRay> rays) const {
  const uint32_t count = static_cast<uint32_t>(std::min<size_t>(rays.size(), kMaxPacketRays));
  std::array<Ray, kMaxPacketRays> packet;
  std::array<Hit, kMaxPacketRays> hits;
  std::array<TraceRequest, kMaxPacketRays> requests;
  std::array<FilterContext, kMaxPacketRays> contexts;
  std::array<HitFilter, kMaxPacketRays> filters;
  for (uint32_t i = 0; i < count; ++i) {
    TracedCameraRay& r = rays[i];
    r.found = r.onOverlay = false;
    r.hit = Hit{};
    r.additive.count = 0;
    r.additive.candidateCount = 0;
    r.fogFreeEnd = false;
    requests[i].kind = RayKind::Camera;
    requests[i].randomBits = r.randomBits;
    requests[i].additive = &r.additive;
  }
  uint32_t remaining = (1u << count) - 1;   // count <= kMaxPacketRays < 32
  // drawOnTop instances first; the rays that miss them go on into the world. The first-person
  // weapon covers a corner of the view: a packet none of whose rays reach its box skips that pass.
  for (const bool overlayPass : {true, false}) {
    const auto& instances = instancesOf(overlayPass);
    if (instances.empty() || remaining == 0) continue;
    const Tlas& tlas = overlayPass ? overlayTlas : worldTlas;
    for (uint32_t r = remaining; r; r &= r - 1) packet[std::countr_zero(r)] = rays[std::countr_zero(r)].ray;
    const uint32_t traced = overlayPass ? tlas.raysMayHit(packet, remaining) : remaining;
    if (traced == 0) continue;
    for (uint32_t r = traced; r; r &= r - 1) {
      const int i = std::countr_zero(r);
      hits[i] = Hit{};
      requests[i].overlay = overlayPass;
      contexts[i] = FilterContext{this, overlayPass, &packet[i], &requests[i]};
      filters[i] = HitFilter{&acceptCandidate, &contexts[i], faceCullFor(RayKind::Camera)};
    }
    const uint32_t found = tlas.intersectPacket(packet, hits, traced, rayMaskFor(RayKind::Camera), filters);
    for (uint32_t r = found; r; r &= r - 1) {
      const int i = std::countr_zero(r);
      rays[i].ray = packet[i];
      rays[i].hit = hits[i];
      rays[i].found = true;
      rays[i].onOverlay = overlayPass;
    }
    remaining &= ~found;
  }
  // The layers in front of each ray's hit: the packet's rays mostly cross the same few layers.
  resolvePacketLayers(*this, rays.first(count));
}

void RenderScene::markFogFreeEnds(std::span<TracedCameraRay> rays) const {
  if (fogs.empty() || rays.empty()) return;
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  float maxT = 0.0f, maxDir = 0.0f;
  bool allHit = true;
  for (const TracedCameraRay& r : rays) {
    allHit = allHit && r.found;   // a miss ends nowhere: left to FogSegment
    const glm::vec3 end = r.ray.origin + r.hit.t * r.ray.dir;
    lo = glm::min(lo, end);
    hi = glm::max(hi, end);
    maxT = std::max(maxT, r.hit.t);
    maxDir = std::max(maxDir, std::fabs(r.ray.dir.x) + std::fabs(r.ray.dir.y) + std::fabs(r.ray.dir.z));
  }
  // An infinite or NaN end anywhere fails these: no ray is marked then.
  if (!allHit || !(maxT < std::numeric_limits<float>::infinity() && maxDir < std::numeric_limits<float>::infinity()))
    return;
  if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z && hi.x - lo.x < std::numeric_limits<float>::infinity() &&
        hi.y - lo.y < std::numeric_limits<float>::infinity() && hi.z - lo.z < std::numeric_limits<float>::infinity()))
    return;
  if (fogMayHoldEndsIn(fogs, lo, hi, fogEndAllowance(lo, hi, maxT, maxDir))) return;
  for (TracedCameraRay& r : rays) r.fogFreeEnd = true;
}

bool RenderScene::occluded(const Ray& shadowRay, const TraceRequest& request) const {
  if (world.empty()) return false;
  Ray ray = shadowRay;
  const FilterContext ctx{this, false, &ray, &request};
  const HitFilter filter{&acceptCandidate, &ctx, faceCullFor(request.kind)};
  return worldTlas.occluded(ray, rayMaskFor(RayKind::Shadow), filter);
}

namespace {

/// The triangle's part of surfaceAt (TriangleMemo's members) for `parts`.
[[gnu::always_inline]] inline void triangleOf(const RenderScene& scene, const RenderInstance& inst, uint32_t prim,
                                              SurfaceParts parts, TriangleMemo& t) {
  const MeshGeometry& g = inst.mesh->geometry;
  const MaterialRecord& material = scene.materialOf(inst, prim);
  t.instance = &inst;
  t.prim = prim;
  t.parts = parts;
  t.material = &material;
  t.i0 = g.indices[3 * size_t{prim}];
  t.i1 = g.indices[3 * size_t{prim} + 1];
  t.i2 = g.indices[3 * size_t{prim} + 2];
  t.p0 = toWorld(inst.objectToWorld, g.positions[t.i0]);
  t.p1 = toWorld(inst.objectToWorld, g.positions[t.i1]);
  t.p2 = toWorld(inst.objectToWorld, g.positions[t.i2]);
  // A layer's colour reads the winding normal only for the side its glow shows on.
  const bool all = parts != SurfaceParts::LayerColour;
  t.len = 0.0f;
  t.geometricNormal = glm::vec3(0.0f, 0.0f, 1.0f);
  if (all || material.emits) {
    const glm::vec3 cross = glm::cross(t.p1 - t.p0, t.p2 - t.p0);
    t.len = glm::length(cross);
    if (t.len > 0.0f) t.geometricNormal = divided(cross, t.len);
  }
  const MaterialDesc& desc = material.desc;
  t.uvArea = triangleUvArea(g, t.i0, t.i1, t.i2, desc.uvTransform);
  t.shineUvArea = all && material.shine != nullptr && desc.stock.shineTexCoords == TexCoordSource::Mesh
                      ? triangleUvArea(g, t.i0, t.i1, t.i2, desc.stock.shineUvTransform)
                      : 0.0f;
}

/// surfaceAt's interpolation at a hit on the triangle `t` holds.
[[gnu::always_inline]] inline SurfaceHit surfaceOn(const Hit& hit, const TriangleMemo& t, SurfaceParts parts) {
  const RenderInstance& inst = *t.instance;
  const MeshGeometry& g = inst.mesh->geometry;
  const MaterialRecord& material = *t.material;
  const uint32_t i0 = t.i0, i1 = t.i1, i2 = t.i2;
  const float w0 = 1.0f - hit.u - hit.v;
  const bool all = parts != SurfaceParts::LayerColour;
  glm::vec3 shadingNormal = t.geometricNormal;
  if (parts == SurfaceParts::All && !g.normals.empty()) {
    const glm::vec3 n = inst.normalToWorld * (w0 * g.normals[i0] + hit.u * g.normals[i1] + hit.v * g.normals[i2]);
    const float nl = glm::length(n);
    if (nl > 0.0f && std::isfinite(nl)) {
      // Keep the interpolated normal on the winding normal's side.
      const glm::vec3 unit = divided(n, nl);   // -n / nl is -(n / nl) to the bit
      shadingNormal = glm::dot(n, t.geometricNormal) >= 0.0f ? unit : -unit;
    }
  }
  const MaterialDesc& desc = material.desc;
  // Mesh uvs through an affine transform.
  auto meshUv = [&](const glm::mat3x2& transform) -> glm::vec2 {
    if (g.uvs.empty()) return transform * glm::vec3(0.0f, 0.0f, 1.0f);
    const glm::vec2 uv = w0 * g.uvs[i0] + hit.u * g.uvs[i1] + hit.v * g.uvs[i2];
    return transform * glm::vec3(uv, 1.0f);
  };
  glm::vec2 uv = meshUv(desc.uvTransform), shineUv(0.0f), lightmapUv(0.0f);
  if (desc.uvWobble.amplitude != 0.0f && desc.baseTexCoords == TexCoordSource::Mesh)
    uv += w0 * desc.uvWobble.offsetAt(g.positions[i0]) + hit.u * desc.uvWobble.offsetAt(g.positions[i1]) +
          hit.v * desc.uvWobble.offsetAt(g.positions[i2]);
  if (all && material.shine != nullptr && desc.stock.shineTexCoords == TexCoordSource::Mesh)
    shineUv = meshUv(desc.stock.shineUvTransform);
  if (all && !g.lightmapUvs.empty()) lightmapUv = w0 * g.lightmapUvs[i0] + hit.u * g.lightmapUvs[i1] + hit.v * g.lightmapUvs[i2];
  glm::vec4 vertexColor(1.0f);
  if (!g.colors.empty()) {
    const glm::vec4& c0 = g.colors[i0];
    const glm::vec4& c1 = g.colors[i1];
    const glm::vec4& c2 = g.colors[i2];
    // w0 a + u b + v c in fused multiply-adds spelled out as the compiler contracted them here
    // (left to it, the contraction changed with `parts`: a layer's colour moved in its last bit).
    vertexColor.a = std::fma(hit.v, c2.a, std::fma(hit.u, c1.a, w0 * c0.a));
    if (!desc.stock.useVertexLight) {
      for (int c = 0; c < 3; ++c) vertexColor[c] = std::fma(hit.v, c2[c], std::fma(w0, c0[c], hit.u * c1[c]));
    } else if (all) {
      // Baked light at the vertices is interpolated in display values, as a raster renderer's
      // Gouraud shading interpolates its 8-bit vertex colours (linear blending is brighter inside).
      // (the mesh's colours encoded at commit: encodeColors)
      const std::vector<glm::vec3>& display = inst.mesh->displayColors;
      for (int c = 0; c < 3; ++c)
        vertexColor[c] = std::fma(hit.v, display[i2][c], std::fma(w0, display[i0][c], hit.u * display[i1][c]));
    }
  }
  const glm::vec2 emissiveUv = desc.emissiveOwnUv ? meshUv(desc.emissiveUvTransform) : uv;
  // Every member from its value, none first filled with its default: GCC fills a default
  // SurfaceHit with `rep stos`, which took a tenth of this function's time.
  return SurfaceHit{.instance = &inst,
                    .material = &material,
                    .prim = hit.prim,
                    .bary = {hit.u, hit.v},
                    .position = w0 * t.p0 + hit.u * t.p1 + hit.v * t.p2,
                    .geometricNormal = t.geometricNormal,
                    .shadingNormal = shadingNormal,
                    .uv = uv,
                    .emissiveUv = emissiveUv,
                    .lightmapUv = lightmapUv,
                    .shineUv = shineUv,
                    .shineUvArea = t.shineUvArea,
                    .vertexColor = vertexColor,
                    .worldArea = 0.5f * t.len,
                    .uvArea = t.uvArea};
}

}  // namespace

SurfaceHit RenderScene::surfaceAt(const Hit& hit, bool overlayHit, SurfaceParts parts, TriangleMemo* memo) const {
  const RenderInstance& inst = instancesOf(overlayHit)[hit.instance];
  if (memo == nullptr) {
    TriangleMemo t;
    triangleOf(*this, inst, hit.prim, parts, t);
    return surfaceOn(hit, t, parts);
  }
  if (memo->instance != &inst || memo->prim != hit.prim || memo->parts != parts) triangleOf(*this, inst, hit.prim, parts, *memo);
  return surfaceOn(hit, *memo, parts);
}

glm::vec3 RenderScene::windingNormal(const RenderInstance& inst, uint32_t prim) const {
  const MeshGeometry& g = inst.mesh->geometry;
  const glm::vec3 p0 = toWorld(inst.objectToWorld, g.positions[g.indices[3 * size_t{prim}]]);
  const glm::vec3 p1 = toWorld(inst.objectToWorld, g.positions[g.indices[3 * size_t{prim} + 1]]);
  const glm::vec3 p2 = toWorld(inst.objectToWorld, g.positions[g.indices[3 * size_t{prim} + 2]]);
  return glm::cross(p1 - p0, p2 - p0);
}

float RenderScene::coverageAt(const RenderInstance& inst, uint32_t prim, glm::vec2 bary) const {
  const MeshGeometry& g = inst.mesh->geometry;
  const MaterialRecord& m = materialOf(inst, prim);
  const uint32_t i0 = g.indices[3 * size_t{prim}];
  const uint32_t i1 = g.indices[3 * size_t{prim} + 1];
  const uint32_t i2 = g.indices[3 * size_t{prim} + 2];
  const float w0 = 1.0f - bary.x - bary.y;
  float alpha = m.desc.baseColor.a * inst.tint.a;
  if (!g.colors.empty()) alpha *= w0 * g.colors[i0].a + bary.x * g.colors[i1].a + bary.y * g.colors[i2].a;
  if (m.base != nullptr) {
    glm::vec2 uv(0.0f);
    if (!g.uvs.empty()) uv = w0 * g.uvs[i0] + bary.x * g.uvs[i1] + bary.y * g.uvs[i2];
    glm::vec2 at = m.desc.uvTransform * glm::vec3(uv, 1.0f);
    if (m.desc.uvWobble.amplitude != 0.0f)
      at += w0 * m.desc.uvWobble.offsetAt(g.positions[i0]) + bary.x * m.desc.uvWobble.offsetAt(g.positions[i1]) +
            bary.y * m.desc.uvWobble.offsetAt(g.positions[i2]);
    alpha *= m.base->sampleFull(at).a;
  }
  return alpha;
}

glm::vec4 RenderScene::baseFactor(const SurfaceHit& s) const {
  const MaterialRecord& m = *s.material;
  // With useVertexLight the vertex colour is baked light (Lightmap integrator), not albedo.
  glm::vec4 vertex = m.desc.stock.useVertexLight || !m.desc.vertexColorTints ? glm::vec4(1.0f, 1.0f, 1.0f, s.vertexColor.a)
                                                                        : s.vertexColor;
  if (!m.desc.vertexAlphaTints) vertex.a = 1.0f;
  return m.desc.baseColor * vertex * s.instance->tint;
}

float RenderScene::baseLod(const SurfaceHit& s, float footprint) const {
  const Texture* base = s.material->base;
  return base != nullptr ? mipLevel(*base, footprint, s.uvArea, s.worldArea) : 0.0f;
}

glm::vec4 RenderScene::baseColor(const SurfaceHit& s, float footprint, TextureFilter filter) const {
  glm::vec4 c = baseFactor(s);
  if (s.material->base != nullptr) c *= s.material->base->sample(s.uv, baseLod(s, footprint), filter);
  if (s.material->cover != nullptr) {
    const CoverTexel cover = coverAt(s, footprint, filter, false);
    c = glm::vec4(glm::mix(glm::vec3(c), cover.color, cover.weight), c.a);
  }
  const float stage = s.material->desc.stock.lightmapStageScale;
  if (stage != 1.0f && stage > 0.0f) {   // stock's doubling lightmap stage: the colour brighter in display values
    for (int k = 0; k < 3; ++k) c[k] = srgbToLinear(std::min(1.0f, stage * linearToSrgb(std::clamp(c[k], 0.0f, 1.0f))));
  }
  return c;
}

CoverTexel RenderScene::coverAt(const SurfaceHit& s, float footprint, TextureFilter filter, bool displayValues) const {
  const MaterialRecord& m = *s.material;
  if (m.cover == nullptr || s.instance == nullptr) return {};
  const MeshGeometry& g = s.instance->mesh->geometry;
  glm::vec2 meshUv(0.0f);
  float uvArea = 0.0f;   // the triangle's area in the cover's uvs: its mip level as baseLod's
  if (!g.uvs.empty() && 3 * size_t{s.prim} + 2 < g.indices.size()) {
    const uint32_t i0 = g.indices[3 * size_t{s.prim}], i1 = g.indices[3 * size_t{s.prim} + 1],
                   i2 = g.indices[3 * size_t{s.prim} + 2];
    meshUv = (1.0f - s.bary.x - s.bary.y) * g.uvs[i0] + s.bary.x * g.uvs[i1] + s.bary.y * g.uvs[i2];
    uvArea = triangleUvArea(g, i0, i1, i2, m.desc.coverUvTransform);
  }
  const glm::vec2 uv = m.desc.coverUvTransform * glm::vec3(meshUv, 1.0f);
  const float lod = mipLevel(*m.cover, footprint, uvArea, s.worldArea);
  const bool stored = displayValues && m.cover->srgb();
  const glm::vec4 texel = stored ? m.cover->sampleStored(uv, lod, filter) : m.cover->sample(uv, lod, filter);
  float weight = std::clamp(texel.a * (m.desc.coverVertexAlpha ? s.vertexColor.a : 1.0f), 0.0f, 1.0f);
  if (weight < m.desc.coverAlphaCutoff) weight = 0.0f;
  glm::vec3 color = glm::clamp(glm::vec3(texel), 0.0f, 1.0f);
  if (displayValues && !stored) color = {linearToSrgb(color.x), linearToSrgb(color.y), linearToSrgb(color.z)};
  return {color, weight};
}

glm::vec4 RenderScene::shineColor(const SurfaceHit& s, float footprint, TextureFilter filter) const {
  const MaterialRecord& m = *s.material;
  if (m.shine == nullptr) return glm::vec4(0.0f);
  return m.shine->sample(s.shineUv, mipLevel(*m.shine, footprint, s.shineUvArea, s.worldArea), filter) * glm::vec4(m.desc.stock.shineColor, 1.0f);
}

glm::vec3 RenderScene::emission(const SurfaceHit& s, bool frontSide) const {
  const MaterialRecord& m = *s.material;
  if (!m.emits || (!frontSide && !m.desc.twoSided)) return glm::vec3(0.0f);
  glm::vec3 e = m.desc.emission;
  if (m.emissive != nullptr) e *= glm::vec3(m.emissive->sample(s.emissiveUv, 0.0f));
  return e;
}

glm::vec3 RenderScene::seenEmission(const SurfaceHit& s, bool frontSide) const {
  const MaterialRecord& m = *s.material;
  if (!m.seenApart) return emission(s, frontSide);
  if (!frontSide && !m.desc.twoSided) return glm::vec3(0.0f);
  glm::vec3 e = m.desc.seenEmission;
  if (e == glm::vec3(0.0f)) return e;
  if (m.emissive != nullptr) e *= glm::vec3(m.emissive->sample(s.emissiveUv, 0.0f));
  return e;
}

const PortalDesc* RenderScene::portalAt(const glm::vec3& position, const glm::vec3& normal,
                                        const glm::vec3& direction) const {
  // Points on the plane within a quarter unit (plus float slack far from the origin), surfaces
  // parallel to it within about 2.5 degrees (either winding).
  constexpr float kPlaneSlack = 0.25f, kRelativeSlack = 1e-5f, kMinAlignment = 0.999f;
  for (const PortalDesc& portal : portals) {
    const float offset = glm::dot(portal.normal, position) - portal.distance;
    if (std::fabs(offset) > kPlaneSlack + kRelativeSlack * std::fabs(portal.distance)) continue;
    if (std::fabs(glm::dot(portal.normal, normal)) < kMinAlignment) continue;
    if (!(glm::dot(portal.normal, direction) < 0.0f)) continue;   // seen from behind
    return &portal;
  }
  return nullptr;
}

uint32_t RenderScene::emissiveIndex(const SurfaceHit& s) const {
  if (s.instance->emissiveOffset == kNoId) return kNoId;
  const size_t i = size_t{s.instance->emissiveOffset} + s.prim;
  return i < emissiveLookup.size() ? emissiveLookup[i] : kNoId;
}

}  // namespace pa
