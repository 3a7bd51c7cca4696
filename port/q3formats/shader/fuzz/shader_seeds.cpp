// Writes the shader fuzzer's seed corpus (generated here, never copied from game data).
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  const std::vector<std::string> seeds = {
      "textures/a/wall\n{\n\tqer_editorimage textures/a/wall.tga\n\tsurfaceparm nomarks\n"
      "\t{\n\t\tmap $lightmap\n\t\trgbGen identity\n\t}\n\t{\n\t\tmap textures/a/wall.tga\n"
      "\t\tblendFunc GL_DST_COLOR GL_ZERO\n\t}\n}\n",
      "sky1 { surfaceparm sky surfaceparm noimpact q3map_sun 1 .9 .8 120 45 60 q3map_sunExt 1 1 1 100 30 40 2 16\n"
      " skyparms env/sky 512 - { map clouds.tga tcMod scale 3 2 tcMod scroll 0.01 0.02 tcMod turb 0 .1 0 .2 } }\n",
      "light { q3map_surfacelight 2500 q3map_lightimage glow.tga q3map_lightRGB 1 0.5 0.2 cull disable\n"
      " { animMap 4 a1.tga a2.tga a3.tga blendFunc add rgbGen wave sin 0.5 0.25 0 1 tcMod rotate 30 } }\n",
      "leaf { cull none deformVertexes wave 100 sin 3 5 0.1 0.5 deformVertexes move 0 0 4 sin 0 1 0 .2\n"
      " { clampMap leaf.tga alphaFunc GE128 depthWrite rgbGen vertex alphaGen lightingSpecular }\n"
      " { map $lightmap blendFunc filter depthFunc equal tcGen lightmap } }\n",
      "fog { surfaceparm fog surfaceparm trans fogparms ( .5 .2 .1 ) 300 sort underwater polygonOffset portal }\n"
      "mirror { portal sort portal { map $whiteimage blendFunc GL_ONE GL_ONE_MINUS_SRC_ALPHA alphaGen portal 256 } }\n",
      "env { { map base.tga rgbGen const ( 0.2 0.4 0.6 ) alphaGen const 0.5 }\n"
      " { map env.tga tcGen environment blendFunc GL_SRC_ALPHA GL_ONE tcMod transform 1 0.5 0 1 0.25 0 }\n"
      " { map x.tga tcGen vector ( 0.01 0 0 ) ( 0 0.01 0 ) tcMod stretch triangle 1 .1 0 .5 detail }\n"
      " { videoMap intro.roq rgbGen oneMinusEntity alphaGen oneMinusVertex tcMod entityTranslate } }\n",
      "/* comment */ a // line\n{ deformVertexes autosprite2 deformVertexes text3 deformVertexes bulge 3 3 1\n"
      " deformVertexes normal 0.5 2 deformVertexes projectionShadow sort 12 nopicmip nomipmaps entityMergable\n"
      " tessSize 128 q3map_globaltexture qer_trans 0.5 light 1 }\n",
      "\"quoted name\" { { map \"a b.tga\" blendFunc blend alphaFunc LT128 rgbGen exactVertex } }\n",
  };
  for (size_t i = 0; i < seeds.size(); ++i)
    std::ofstream(dir / ("seed" + std::to_string(i) + ".shader"), std::ios::binary) << seeds[i];
  return 0;
}
