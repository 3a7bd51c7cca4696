#include "port/engine_glue/scene.h"

#include <cmath>

namespace glue {
namespace {

bool finite3(const float* v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

}  // namespace

bool entityIsFinite(const q3abi::refEntity_t& e) {
  return finite3(e.origin) && finite3(e.oldorigin) && finite3(e.lightingOrigin) &&
         finite3(e.axis[0]) && finite3(e.axis[1]) && finite3(e.axis[2]) &&
         std::isfinite(e.backlerp) && std::isfinite(e.radius) && std::isfinite(e.rotation);
}

void SceneFrame::clear() {
  entities_.clear();
  polys_.clear();
  polyVerts_.clear();
  lights_.clear();
}

bool SceneFrame::addEntity(const q3abi::refEntity_t& entity) {
  if (entities_.size() >= kMaxEntities) return false;
  if (entity.reType < 0 || entity.reType >= q3abi::RT_MAX_REF_ENTITY_TYPE) return false;
  if (!entityIsFinite(entity)) return false;
  entities_.push_back(entity);
  return true;
}

bool SceneFrame::addPolys(q3abi::qhandle_t shader, int vertsPerPoly,
                          const q3abi::polyVert_t* verts, int count) {
  if (verts == nullptr || vertsPerPoly < 3 || count <= 0) return false;
  for (int p = 0; p < count; ++p) {
    if (polys_.size() >= kMaxPolys ||
        polyVerts_.size() + static_cast<size_t>(vertsPerPoly) > kMaxPolyVerts)
      return false;   // the stock renderer drops the rest silently (developer warning)
    const q3abi::polyVert_t* first = verts + static_cast<size_t>(p) * vertsPerPoly;
    bool finite = true;
    for (int v = 0; v < vertsPerPoly; ++v)
      finite = finite && finite3(first[v].xyz) && std::isfinite(first[v].st[0]) &&
               std::isfinite(first[v].st[1]);
    if (!finite) continue;
    polys_.push_back({shader, static_cast<uint32_t>(polyVerts_.size()),
                      static_cast<uint32_t>(vertsPerPoly)});
    polyVerts_.insert(polyVerts_.end(), first, first + vertsPerPoly);
  }
  return true;
}

void SceneFrame::addLight(const float* origin, float radius, float r, float g, float b,
                          bool additive) {
  if (origin == nullptr || !(radius > 0.0f) || !finite3(origin) || lights_.size() >= kMaxLights)
    return;
  if (!std::isfinite(r) || !std::isfinite(g) || !std::isfinite(b)) return;
  lights_.push_back({{origin[0], origin[1], origin[2]}, radius, {r, g, b}, additive});
}

}  // namespace glue
