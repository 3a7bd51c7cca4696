// The C boundary: GetRefAPI (the module's only exported symbol) and the refexport_t table.
// Each entry point runs its Module method inside a try block. Exceptions never cross into the
// engine: a DropError/FatalError is turned into ri.Error *after* the try block has unwound, so
// no C++ object is alive between ri.Error's longjmp and the engine; anything else becomes a
// warning and the call returns a neutral value.
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <type_traits>

#include "port/engine_glue/module.h"

namespace glue {
namespace {

/// The module's single owner of state: the import table and the Module built from it.
struct ModuleHolder {
  q3abi::refimport_t ri{};
  bool haveImports = false;
  std::unique_ptr<Module> module;
};

ModuleHolder& holder() {
  static ModuleHolder instance;
  return instance;
}

void copyMessage(char (&out)[1024], const char* prefix, const char* what) {
  std::snprintf(out, sizeof out, "%s%s", prefix, what != nullptr ? what : "unknown error");
}

/// Runs body(module) and keeps exceptions inside the module (see the file comment).
template <typename Result, typename Body>
Result guarded(const char* where, Body&& body) {
  char message[1024];
  message[0] = '\0';
  int errorLevel = -1;
  {
    ModuleHolder& h = holder();
    if (!h.haveImports) {
      if constexpr (std::is_void_v<Result>) return;
      else return Result{};
    }
    try {
      if (!h.module) h.module = std::make_unique<Module>(h.ri);
      return body(*h.module);
    } catch (const FatalError& error) {
      copyMessage(message, "", error.what());
      errorLevel = q3abi::ERR_FATAL;
    } catch (const DropError& error) {
      copyMessage(message, "", error.what());
      errorLevel = q3abi::ERR_DROP;
    } catch (const std::bad_alloc&) {
      copyMessage(message, "out of memory in ", where);
      errorLevel = q3abi::ERR_DROP;
    } catch (const std::exception& error) {
      h.ri.Printf(q3abi::PRINT_WARNING, "pathtracer: %s: %s\n", where, error.what());
    } catch (...) {
      h.ri.Printf(q3abi::PRINT_WARNING, "pathtracer: %s: unknown exception\n", where);
    }
  }
  // Every C++ object of this call is gone: safe to longjmp back into the engine.
  if (errorLevel >= 0) holder().ri.Error(errorLevel, "pathtracer: %s", message);
  if constexpr (!std::is_void_v<Result>) return Result{};
}

void shutdownEntry(q3abi::qboolean destroyWindow) {
  guarded<void>("Shutdown", [&](Module& m) { m.shutdown(destroyWindow != 0); });
  if (destroyWindow != 0) {
    // The engine will dlclose us: drop all state now, while its functions are still valid.
    try {
      holder().module.reset();
    } catch (...) {
    }
  }
}

q3abi::refexport_t makeExports() {
  using namespace q3abi;
  refexport_t re{};
  re.Shutdown = shutdownEntry;
  re.BeginRegistration = [](glconfig_t* config) {
    guarded<void>("BeginRegistration", [&](Module& m) { m.beginRegistration(config); });
  };
  re.RegisterModel = [](const char* name) {
    return guarded<qhandle_t>("RegisterModel", [&](Module& m) { return m.registerModel(name); });
  };
  re.RegisterSkin = [](const char* name) {
    return guarded<qhandle_t>("RegisterSkin", [&](Module& m) { return m.registerSkin(name); });
  };
  re.RegisterShader = [](const char* name) {
    return guarded<qhandle_t>("RegisterShader", [&](Module& m) { return m.registerShader(name); });
  };
  re.RegisterShaderNoMip = [](const char* name) {
    return guarded<qhandle_t>("RegisterShaderNoMip",
                              [&](Module& m) { return m.registerShaderNoMip(name); });
  };
  re.LoadWorld = [](const char* name) {
    guarded<void>("LoadWorld", [&](Module& m) { m.loadWorld(name); });
  };
  re.SetWorldVisData = [](const byte* vis) {
    guarded<void>("SetWorldVisData", [&](Module& m) { m.setWorldVisData(vis); });
  };
  re.EndRegistration = [] { guarded<void>("EndRegistration", [](Module& m) { m.endRegistration(); }); };
  re.ClearScene = [] { guarded<void>("ClearScene", [](Module& m) { m.clearScene(); }); };
  re.AddRefEntityToScene = [](const refEntity_t* entity) {
    guarded<void>("AddRefEntityToScene", [&](Module& m) { m.addRefEntityToScene(entity); });
  };
  re.AddPolyToScene = [](qhandle_t shader, int numVerts, const polyVert_t* verts, int count) {
    guarded<void>("AddPolyToScene",
                  [&](Module& m) { m.addPolyToScene(shader, numVerts, verts, count); });
  };
  re.LightForPoint = [](vec3_t point, vec3_t ambient, vec3_t directed, vec3_t direction) {
    return guarded<int>("LightForPoint", [&](Module& m) {
      return m.lightForPoint(point, ambient, directed, direction);
    });
  };
  re.AddLightToScene = [](const vec3_t origin, float intensity, float r, float g, float b) {
    guarded<void>("AddLightToScene",
                  [&](Module& m) { m.addLightToScene(origin, intensity, r, g, b); });
  };
  re.AddAdditiveLightToScene = [](const vec3_t origin, float intensity, float r, float g, float b) {
    guarded<void>("AddAdditiveLightToScene",
                  [&](Module& m) { m.addAdditiveLightToScene(origin, intensity, r, g, b); });
  };
  re.RenderScene = [](const refdef_t* view) {
    guarded<void>("RenderScene", [&](Module& m) { m.renderScene(view); });
  };
  re.SetColor = [](const float* rgba) {
    guarded<void>("SetColor", [&](Module& m) { m.setColor(rgba); });
  };
  re.DrawStretchPic = [](float x, float y, float w, float h, float s1, float t1, float s2,
                         float t2, qhandle_t shader) {
    guarded<void>("DrawStretchPic",
                  [&](Module& m) { m.drawStretchPic(x, y, w, h, s1, t1, s2, t2, shader); });
  };
  re.DrawStretchRaw = [](int x, int y, int w, int h, int cols, int rows, const byte* data,
                         int client, qboolean dirty) {
    guarded<void>("DrawStretchRaw", [&](Module& m) {
      m.drawStretchRaw(x, y, w, h, cols, rows, data, client, dirty != 0);
    });
  };
  re.UploadCinematic = [](int w, int h, int cols, int rows, const byte* data, int client,
                          qboolean dirty) {
    guarded<void>("UploadCinematic", [&](Module& m) {
      m.uploadCinematic(w, h, cols, rows, data, client, dirty != 0);
    });
  };
  re.BeginFrame = [](int stereo) {
    guarded<void>("BeginFrame", [&](Module& m) { m.beginFrame(stereo); });
  };
  re.EndFrame = [](int* frontEndMsec, int* backEndMsec) {
    guarded<void>("EndFrame", [&](Module& m) { m.endFrame(frontEndMsec, backEndMsec); });
  };
  re.MarkFragments = [](int numPoints, const vec3_t* points, const vec3_t projection,
                        int maxPoints, vec3_t pointBuffer, int maxFragments,
                        markFragment_t* fragments) {
    return guarded<int>("MarkFragments", [&](Module& m) {
      return m.markFragments(numPoints, points, projection, maxPoints, pointBuffer, maxFragments,
                             fragments);
    });
  };
  re.LerpTag = [](orientation_t* tag, qhandle_t model, int startFrame, int endFrame, float frac,
                  const char* tagName) {
    return guarded<int>("LerpTag", [&](Module& m) {
      return m.lerpTag(tag, model, startFrame, endFrame, frac, tagName);
    });
  };
  re.ModelBounds = [](qhandle_t model, vec3_t mins, vec3_t maxs) {
    guarded<void>("ModelBounds", [&](Module& m) { m.modelBounds(model, mins, maxs); });
  };
  re.RegisterFont = [](const char* fontName, int pointSize, fontInfo_t* font) {
    guarded<void>("RegisterFont", [&](Module& m) { m.registerFont(fontName, pointSize, font); });
  };
  re.RemapShader = [](const char* oldShader, const char* newShader, const char* timeOffset) {
    guarded<void>("RemapShader",
                  [&](Module& m) { m.remapShader(oldShader, newShader, timeOffset); });
  };
  re.GetEntityToken = [](char* buffer, int size) {
    return guarded<qboolean>("GetEntityToken",
                             [&](Module& m) { return m.getEntityToken(buffer, size) ? 1 : 0; });
  };
  re.inPVS = [](const vec3_t p1, const vec3_t p2) {
    return guarded<qboolean>("inPVS", [&](Module& m) { return m.inPVS(p1, p2) ? 1 : 0; });
  };
  re.TakeVideoFrame = [](int width, int height, byte* captureBuffer, byte* encodeBuffer,
                         qboolean motionJpeg) {
    guarded<void>("TakeVideoFrame", [&](Module& m) {
      m.takeVideoFrame(width, height, captureBuffer, encodeBuffer, motionJpeg != 0);
    });
  };
  return re;
}

}  // namespace

/// Runs a console command's handler on the live module (commands are plain C callbacks).
void runCommand(const char* name, void (*handler)(Module&)) {
  guarded<void>(name, [&](Module& m) { handler(m); });
}

}  // namespace glue

extern "C" __attribute__((visibility("default"))) q3abi::refexport_t* GetRefAPI(
    int apiVersion, q3abi::refimport_t* imports) {
  static q3abi::refexport_t exports = glue::makeExports();
  if (imports == nullptr) return nullptr;
  if (apiVersion != q3abi::kRefApiVersion) {
    imports->Printf(q3abi::PRINT_ALL,
                    "pathtracer: mismatched refresh API version %d (this module speaks %d)\n",
                    apiVersion, q3abi::kRefApiVersion);
    return nullptr;
  }
  glue::ModuleHolder& h = glue::holder();
  try {
    h.module.reset();
    h.ri = *imports;
    h.haveImports = true;
    imports->Printf(q3abi::PRINT_ALL,
                    "PathArena path tracer renderer (pathtracer), refresh API %d\n", apiVersion);
  } catch (...) {
    return nullptr;
  }
  return &exports;
}
