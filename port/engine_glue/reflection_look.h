#pragma once
// Models and effects: a stage with tcGen environment (chrome weapons, powerups, player suits)
// as a renderer material that reads its image through pa::TexCoordSource::ReflectionSphere.
//
// Lightmap preset: the image at the mirrored view direction in the entity's own frame (the
// instance's object space), times the stage's colour (the vertex colour: lightingDiffuse grid
// light, entity colour or white), as stock opengl1 draws it; later additive stages stay layers.
// Direct / path presets: the same lookup is the diffuse albedo, under a glossy lobe of weight
// kReflectionSpecular that reflects the real scene. Chosen over the image's average colour as a
// flat tint: the lookup keeps what the artist painted (the gold of a powerup, the dark bands of a
// chrome map), costs one texture fetch, and matches the lightmap preset where lighting is flat;
// the glossy lobe adds the view-dependent light a physically based surface of that kind shows.
// A shine stage over an opaque base (ShineLook) goes into the base's own material (a second
// texture composed after the base), never as coincident duplicate triangles: in a ray tracer
// the closest-hit tie between two coincident triangles decides which one is seen.
#include "port/engine_glue/shader_scripts.h"
#include "renderer/scene/scene_types.h"

namespace glue {

/// Weight of the glossy lobe of environment-mapped materials in the traced presets (the world
/// bridge gives env-mapped world shaders the same 0.5).
inline constexpr float kReflectionSpecular = 0.5f;

/// Sets desc's base texture coordinates from look: for a tcGen environment stage the reflection
/// sphere, the stage's tcMods at time 0 as uvTransform (scale, rotate, transform; animated tcMods
/// are frozen: model materials are cached per shader) and the glossy lobe. Leaves other looks as
/// they are.
void applyReflectionLook(const ShaderLook& look, pa::MaterialDesc& desc);

/// Sets desc's shine from look.shine (an opaque base with an environment-mapped stage over it),
/// given the renderer texture of the shine image: reflection-sphere uvs (mesh uvs for a filter
/// stage without tcGen environment) through the stage's tcMods at time 0, its colour (rgbGen const as linear colour; lightingDiffuse / vertex: the vertex
/// colour, i.e. the entity light of models; other rgbGens: white), its blend (add: Add;
/// gl_dst_color gl_src_color: Modulate2x; gl_dst_color gl_dst_alpha: MultiplyAdd) and, for the
/// traced presets, the glossy lobe kReflectionSpecular (environment-mapped shines only). Leaves desc as it is when look has no
/// shine, the texture is kNoId or desc is not opaque / alpha-tested.
void applyShineLook(const ShaderLook& look, pa::TextureId shineTexture, pa::MaterialDesc& desc);

}  // namespace glue
