// ViewRenderer for builds without the path tracer (pa_scene / q3 parsers not built): 2D works,
// 3D views stay black and the console says why once.
#include "port/engine_glue/engine.h"
#include "port/engine_glue/views.h"

namespace glue {

struct ViewRenderer::Impl {
  const Engine& engine;
  bool warned = false;
};

ViewRenderer::ViewRenderer(const Engine& engine, int, bool, bool) : impl_(new Impl{engine}) {}
ViewRenderer::~ViewRenderer() = default;
bool ViewRenderer::available() { return false; }

void ViewRenderer::loadWorld(const World&, const ShaderScripts&, ImageCache&) {}
void ViewRenderer::clearWorld() {}
void ViewRenderer::setPicture(const PictureSettings&) {}
void ViewRenderer::shadersChanged() {}
void ViewRenderer::prepareForPlay(ShaderRegistry&, const TracerSettings&, bool) {}
std::pair<int, int> ViewRenderer::warmUp(const TracerSettings&, int, int) { return {0, 0}; }

std::optional<TracedPicture> ViewRenderer::render(const q3abi::refdef_t&, const SceneFrame&,
                                                  const TracerSettings&, ShaderRegistry&,
                                                  const ModelRegistry&, const World*) {
  if (!impl_->warned) {
    impl_->engine.warn("3D views are not traced in this build (pa::Renderer not linked yet)");
    impl_->warned = true;
  }
  return std::nullopt;
}

void ViewRenderer::start(const q3abi::refdef_t& view, const SceneFrame& scene, const TracerSettings& settings,
                         ShaderRegistry& shaders, const ModelRegistry& models, const World* world) {
  (void)render(view, scene, settings, shaders, models, world);
}

bool ViewRenderer::started() const { return false; }

std::optional<TracedPicture> ViewRenderer::finish() { return std::nullopt; }

}  // namespace glue
