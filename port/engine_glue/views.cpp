#include "port/engine_glue/views.h"

#include "port/engine_glue/engine.h"

namespace glue {

ViewRenderer::ViewRenderer(const Engine& engine, int threads) : engine_(engine), threads_(threads) {}
ViewRenderer::~ViewRenderer() = default;

void ViewRenderer::loadWorld(const World&, const std::vector<uint8_t>&, const ShaderScripts&,
                             ImageCache&) {}

void ViewRenderer::clearWorld() {}

void ViewRenderer::shadersChanged() {}

std::optional<TracedPicture> ViewRenderer::render(const q3abi::refdef_t&, const SceneFrame&,
                                                  const TracerSettings&, ShaderRegistry&,
                                                  const ModelRegistry&, bool) {
  if (!warnedUnavailable_) {
    engine_.warn("3D views are not traced in this build (pa::Renderer not linked yet)");
    warnedUnavailable_ = true;
  }
  return std::nullopt;
}

}  // namespace glue
