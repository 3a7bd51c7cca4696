// Soak test of the renderer module: 20 map loads cycling over real OpenArena maps, with the
// registrations, scene adds, traced views and 2D of a game frame each cycle, and a vid_restart
// (Shutdown(1), dlclose, dlopen, GetRefAPI) every third cycle — what the engine does over a
// long session. Asserts that neither resident memory nor the thread count grows once warmed up.
// Built with PATHARENA_SANITIZE (see tests/soak/sanitized_glue_soak.sh) ASan/UBSan/LSan also
// check every access and report any leak at exit. Needs an X display (runs under xvfb-run).
#include <dlfcn.h>
#include <link.h>
#include <malloc.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "fake_engine.h"
#include "port/q3formats/vfs/game_filesystem.h"

#if defined(__SANITIZE_ADDRESS__)
#define PA_SOAK_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PA_SOAK_ASAN 1
#endif
#endif

namespace {

using q3abi::refexport_t;

/// Maps visited in turn: stock, patched (a later pk3 replaces the bsp) and community maps.
const char* const kMapCycle[] = {"oa_dm1", "aggressor", "oacmpdm1", "q3dm6ish", "oa_ctf2"};
/// A vid_restart follows every kRestartEvery-th map load.
constexpr int kRestartEvery = 3;
/// Map loads done before memory and threads are expected to be flat (one tour of the maps).
constexpr int kWarmupLoads = static_cast<int>(std::size(kMapCycle)) + 1;
/// Allowed resident growth after warm-up. A leaked map (BVH, textures) costs tens of MiB; the
/// allocator's caches move by up to 1 MiB between otherwise identical states (measured).
constexpr long kResidentSlackKiB = 6 * 1024;

/// What the process holds at one moment.
struct ProcessSample {
  long residentKiB = 0;
  int threads = 0;
};

ProcessSample sampleProcess() {
  malloc_trim(0);   // hand freed pages back so that resident memory counts live data
  ProcessSample sample;
  long pagesTotal = 0, pagesResident = 0;
  if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(statm, "%ld %ld", &pagesTotal, &pagesResident) != 2) pagesResident = 0;
    std::fclose(statm);
  }
  sample.residentKiB = pagesResident * (sysconf(_SC_PAGESIZE) / 1024);
  for ([[maybe_unused]] const auto& task : std::filesystem::directory_iterator("/proc/self/task"))
    ++sample.threads;
  return sample;
}

int soakCycles() {
  const char* text = std::getenv("PA_SOAK_CYCLES");
  const int cycles = text != nullptr ? std::atoi(text) : 20;
  return std::clamp(cycles, 1, 1000);
}

/// Keeps the system's GL stack (libGL, Mesa's GLX and DRI driver, LLVM) loaded for the rest of
/// the process, as a long-running game has it: SDL unloads libGL whenever the module closes its
/// window, and a library reloaded on every vid_restart would show up as growth that is not the
/// module's, and, once unloaded, leaves LeakSanitizer unable to name its frames.
void pinSystemGraphicsLibraries() {
  std::vector<std::string> names;
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* out) {
        const std::string name = info->dlpi_name != nullptr ? info->dlpi_name : "";
        for (const char* part : {"libGL", "libGLX", "libGLdispatch", "libglapi", "_dri.so", "libgallium",
                                 "libLLVM", "libdrm", "libxcb-glx"})
          if (name.find(part) != std::string::npos) {
            static_cast<std::vector<std::string>*>(out)->push_back(name);
            break;
          }
        return 0;
      },
      &names);
  for (const std::string& name : names) dlopen(name.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
}

/// Unmounts the game data before static destruction (physfs' registry is a static too).
class UnmountGameData : public ::testing::Environment {
 public:
  void TearDown() override { fake::engine().game.reset(); }
};
const auto* const kUnmount = ::testing::AddGlobalTestEnvironment(new UnmountGameData);

/// The loaded module, as the engine holds it.
class LoadedModule {
 public:
  LoadedModule() = default;
  LoadedModule(const LoadedModule&) = delete;
  LoadedModule& operator=(const LoadedModule&) = delete;
  ~LoadedModule() { unload(); }

  /// dlopen + GetRefAPI (CL_InitRef).
  void load() {
    library_ = dlopen(GLUE_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(library_, nullptr) << dlerror();
    using GetRefApi = refexport_t* (*)(int, q3abi::refimport_t*);
    auto getRefApi = reinterpret_cast<GetRefApi>(dlsym(library_, "GetRefAPI"));
    ASSERT_NE(getRefApi, nullptr);
    imports_ = fake::imports();
    re_ = getRefApi(q3abi::kRefApiVersion, &imports_);
    ASSERT_NE(re_, nullptr);
  }
  /// Shutdown(qtrue) + dlclose (CL_ShutdownRef).
  void unload() {
    if (re_ != nullptr) re_->Shutdown(1);
    re_ = nullptr;
    if (library_ != nullptr) {
      EXPECT_EQ(dlclose(library_), 0) << dlerror();
    }
    library_ = nullptr;
    fake::engine().commands.clear();
  }
  refexport_t& re() { return *re_; }

 private:
  void* library_ = nullptr;
  q3abi::refimport_t imports_{};
  refexport_t* re_ = nullptr;
};

/// Where a player would stand: the first spawn point of the entity string.
struct Spawn {
  float origin[3] = {0, 0, 0};
  bool found = false;
};

Spawn findSpawn(refexport_t& re) {
  Spawn spawn;
  char token[1024];
  std::map<std::string, std::string> fields;
  while (re.GetEntityToken(token, sizeof token)) {
    if (std::strcmp(token, "{") == 0) {
      fields.clear();
    } else if (std::strcmp(token, "}") == 0) {
      const std::string& type = fields["classname"];
      if ((type == "info_player_deathmatch" || type == "info_player_start") &&
          std::sscanf(fields["origin"].c_str(), "%f %f %f", &spawn.origin[0], &spawn.origin[1],
                      &spawn.origin[2]) == 3) {
        spawn.origin[2] += 26.0f;   // eye height above the spawn point
        spawn.found = true;
        break;
      }
    } else {
      const std::string key = token;
      if (!re.GetEntityToken(token, sizeof token)) break;
      fields[key] = token;
    }
  }
  while (re.GetEntityToken(token, sizeof token)) {
  }   // drain: the cgame reads the entity string from the start after a load
  return spawn;
}

/// Handles a game registers for a map, as cgame does (some fail on purpose: missing names).
struct Registered {
  q3abi::qhandle_t white = 0, chars = 0, plasma = 0, mark = 0, tracer = 0;
  q3abi::qhandle_t head = 0, weapon = 0, headSkin = 0;
  int subModels = 0;
};

class ModuleSoak : public ::testing::Test {
 protected:
  void SetUp() override {
    fake::reset();
    if (!fake::mountInstalledGame()) GTEST_SKIP() << "OpenArena data not installed";
    for (const char* map : kMapCycle) {
      void* probe = nullptr;
      const std::string path = std::string("maps/") + map + ".bsp";
      if (fake::imports().FS_ReadFile(path.c_str(), &probe) > 0) maps_.push_back(path);
      if (probe != nullptr) fake::imports().FS_FreeFile(probe);
    }
    if (maps_.size() < 2) GTEST_SKIP() << "fewer than two of the soak maps are installed";
    fake::FakeEngine& e = fake::engine();
    e.setCvar("r_mode", "-1");
    e.setCvar("r_customwidth", "160");
    e.setCvar("r_customheight", "120");
    e.setCvar("r_fullscreen", "0");
    e.setCvar("r_pt_scale", "0.25");
    e.setCvar("r_pt_threads", "2");
  }

  /// BeginRegistration's UI shaders (CL_InitRenderer) and the map's registrations (cgame).
  Registered registerForMap(refexport_t& re, const std::string& map) {
    Registered r;
    std::memset(&config_, 0, sizeof config_);
    re.BeginRegistration(&config_);
    EXPECT_EQ(config_.vidWidth, 160);
    r.chars = re.RegisterShader("gfx/2d/bigchars");
    r.white = re.RegisterShader("white");
    re.RegisterShader("console");
    q3abi::fontInfo_t font{};
    re.RegisterFont("fonts/font", 16, &font);
    re.LoadWorld(map.c_str());
    for (int i = 1; i < 256; ++i) {   // every brush sub-model, as cgame does
      char subModel[16];
      std::snprintf(subModel, sizeof subModel, "*%d", i);
      if (re.RegisterModel(subModel) == 0) break;
      r.subModels = i;
    }
    r.head = re.RegisterModel("models/players/sarge/head.md3");
    r.headSkin = re.RegisterSkin("models/players/sarge/head_default.skin");
    r.weapon = re.RegisterModel("models/weapons2/rocketl/rocketl.md3");
    r.plasma = re.RegisterShader("sprites/plasma1");
    r.mark = re.RegisterShader("gfx/damage/bullet_mrk");
    r.tracer = re.RegisterShader("gfx/misc/tracer");
    EXPECT_EQ(re.RegisterModel("models/soak/not_there.md3"), 0);
    q3abi::orientation_t tag{};
    re.LerpTag(&tag, r.weapon, 0, 0, 0.0f, "tag_flash");
    re.EndRegistration();
    return r;
  }

  /// A game frame: the world view with models, effects, a decal and a light; a HUD head view
  /// with no world; then 2D.
  void renderFrame(refexport_t& re, const Registered& r, const Spawn& spawn, int frame) {
    re.BeginFrame(q3abi::STEREO_CENTER);
    re.ClearScene();
    const float* eye = spawn.origin;
    q3abi::refEntity_t model{};
    model.reType = q3abi::RT_MODEL;
    model.hModel = r.weapon;
    model.axis[0][0] = model.axis[1][1] = model.axis[2][2] = 1.0f;
    model.origin[0] = eye[0] + 48.0f;
    model.origin[1] = eye[1];
    model.origin[2] = eye[2] - 8.0f;
    std::memcpy(model.oldorigin, model.origin, sizeof model.origin);
    model.shaderRGBA[0] = model.shaderRGBA[1] = model.shaderRGBA[2] = model.shaderRGBA[3] = 255;
    re.AddRefEntityToScene(&model);
    q3abi::refEntity_t head = model;
    head.hModel = r.head;
    head.customSkin = r.headSkin;
    head.origin[1] += 24.0f;
    re.AddRefEntityToScene(&head);
    if (r.subModels > 0) {
      q3abi::refEntity_t mover{};
      mover.reType = q3abi::RT_MODEL;
      mover.hModel = re.RegisterModel("*1");
      mover.axis[0][0] = mover.axis[1][1] = mover.axis[2][2] = 1.0f;
      mover.origin[2] = static_cast<float>(frame);   // moves a little every frame
      re.AddRefEntityToScene(&mover);
    }
    q3abi::refEntity_t sprite{};
    sprite.reType = q3abi::RT_SPRITE;
    sprite.customShader = r.plasma;
    sprite.radius = 8.0f;
    std::memcpy(sprite.origin, model.origin, sizeof sprite.origin);
    sprite.origin[2] += 16.0f;
    sprite.shaderRGBA[0] = sprite.shaderRGBA[3] = 255;
    re.AddRefEntityToScene(&sprite);
    q3abi::refEntity_t beam{};
    beam.reType = q3abi::RT_RAIL_CORE;
    beam.customShader = r.tracer;
    std::memcpy(beam.origin, model.origin, sizeof beam.origin);
    std::memcpy(beam.oldorigin, eye, sizeof beam.oldorigin);
    beam.oldorigin[2] -= 12.0f;
    beam.shaderRGBA[1] = beam.shaderRGBA[3] = 255;
    re.AddRefEntityToScene(&beam);
    q3abi::polyVert_t decal[4]{};
    const float corners[4][2] = {{-8, -8}, {8, -8}, {8, 8}, {-8, 8}};
    for (int i = 0; i < 4; ++i) {
      decal[i].xyz[0] = model.origin[0] + corners[i][0];
      decal[i].xyz[1] = model.origin[1] + corners[i][1];
      decal[i].xyz[2] = eye[2] - 20.0f;
      decal[i].st[0] = corners[i][0] > 0 ? 1.0f : 0.0f;
      decal[i].st[1] = corners[i][1] > 0 ? 1.0f : 0.0f;
      decal[i].modulate[0] = decal[i].modulate[1] = decal[i].modulate[2] = decal[i].modulate[3] = 255;
    }
    re.AddPolyToScene(r.mark, 4, decal, 1);
    re.AddLightToScene(model.origin, 200.0f, 1.0f, 0.6f, 0.2f);
    float ambient[3], directed[3], direction[3];
    re.LightForPoint(const_cast<float*>(eye), ambient, directed, direction);
    q3abi::refdef_t view{};
    view.width = 160;
    view.height = 120;
    view.fov_x = 90.0f;
    view.fov_y = 73.7f;
    std::memcpy(view.vieworg, eye, sizeof view.vieworg);
    view.viewaxis[0][0] = view.viewaxis[1][1] = view.viewaxis[2][2] = 1.0f;
    view.time = frame * 16;
    std::memset(view.areamask, 0, sizeof view.areamask);
    re.RenderScene(&view);

    re.ClearScene();   // the HUD head: no world
    q3abi::refEntity_t hudHead = head;
    hudHead.origin[0] = 60.0f;
    hudHead.origin[1] = hudHead.origin[2] = 0.0f;
    re.AddRefEntityToScene(&hudHead);
    q3abi::refdef_t hud{};
    hud.x = 4;
    hud.y = 4;
    hud.width = hud.height = 24;
    hud.fov_x = hud.fov_y = 30.0f;
    hud.viewaxis[0][0] = hud.viewaxis[1][1] = hud.viewaxis[2][2] = 1.0f;
    hud.rdflags = q3abi::RDF_NOWORLDMODEL;
    re.RenderScene(&hud);

    const float tint[4] = {1.0f, 1.0f, 0.5f, 0.8f};
    re.SetColor(tint);
    re.DrawStretchPic(0, 100, 160, 20, 0, 0, 1, 1, r.white);
    re.SetColor(nullptr);
    re.DrawStretchPic(8, 104, 8, 8, 0.25f, 0.25f, 0.3125f, 0.3125f, r.chars);
    re.EndFrame(nullptr, nullptr);
  }

  std::vector<std::string> maps_;
  q3abi::glconfig_t config_{};
};

TEST_F(ModuleSoak, MapChangesAndVidRestartsHoldMemoryAndThreadsFlat) {
  const int cycles = soakCycles();
  const char* presets[] = {"lightmap", "direct", "path"};
  LoadedModule module;
  module.load();
  if (HasFatalFailure()) return;

  std::vector<ProcessSample> afterUnload;                 // module dlclosed
  std::map<std::string, std::vector<ProcessSample>> withMap;   // that map loaded, same frames
  for (int cycle = 0; cycle < cycles; ++cycle) {
    const std::string& map = maps_[static_cast<size_t>(cycle) % maps_.size()];
    SCOPED_TRACE("map load " + std::to_string(cycle + 1) + ": " + map);
    fake::engine().setCvar("r_pt_preset", presets[cycle % 3]);
    refexport_t& re = module.re();
    re.Shutdown(0);   // the engine's map change: twice in a row
    re.Shutdown(0);
    fake::engine().prints.clear();
    const Registered registered = registerForMap(re, map);
    if (cycle == 0) pinSystemGraphicsLibraries();
    ASSERT_TRUE(fake::engine().printed("loaded " + map)) << "LoadWorld failed";
    ASSERT_GT(registered.weapon, 0);
    ASSERT_GT(registered.head, 0);
    const Spawn spawn = findSpawn(re);
    EXPECT_TRUE(spawn.found);
    for (int frame = 0; frame < 3; ++frame) renderFrame(re, registered, spawn, frame);
    EXPECT_EQ(fake::engine().lastErrorLevel, -1) << fake::engine().lastError;
    EXPECT_FALSE(fake::engine().printed("RenderScene:")) << "a traced view failed";
    withMap[map].push_back(sampleProcess());

    if (cycle % kRestartEvery == kRestartEvery - 1 || cycle == cycles - 1) {
      module.unload();   // vid_restart: the module is unloaded...
      afterUnload.push_back(sampleProcess());
      std::printf("[soak] after load %2d (%s) and unload: resident %ld KiB, %d threads\n",
                  cycle + 1, map.c_str(), afterUnload.back().residentKiB,
                  afterUnload.back().threads);
      std::fflush(stdout);   // progress shows even if a slow (sanitized) run times out
      if (cycle != cycles - 1) {
        module.load();   // ... and loaded again; the next map load re-registers everything
        if (HasFatalFailure()) return;
      }
    }
  }

  // Threads: the tracer's pool is created once per process (libtbb stays loaded); every
  // GL context's and the module's own threads end with Shutdown(1).
  for (size_t i = 1; i < afterUnload.size(); ++i)
    EXPECT_LE(afterUnload[i].threads, afterUnload[0].threads)
        << "threads accumulate across vid_restarts (unload " << i + 1 << ")";
  for (const auto& [map, samples] : withMap)
    for (size_t i = 1; i < samples.size(); ++i)
      EXPECT_LE(samples[i].threads, samples[0].threads) << map << " load " << i + 1;

#ifdef PA_SOAK_ASAN
  // ASan's quarantine and shadow memory make resident size meaningless; LeakSanitizer checks
  // every allocation at exit instead.
  std::printf("[soak] AddressSanitizer build: resident-memory bound not checked\n");
#else
  // Resident memory: compare states that should be identical, once everything is warm.
  if (cycles > kWarmupLoads) {
    const size_t warm = static_cast<size_t>(kWarmupLoads / kRestartEvery - 1);   // after load 6
    for (size_t i = warm + 1; i < afterUnload.size(); ++i)
      EXPECT_LE(afterUnload[i].residentKiB - afterUnload[warm].residentKiB, kResidentSlackKiB)
          << "resident memory grows across vid_restarts (unload " << i + 1 << ")";
    // With a map loaded, resident size differs from load to load by up to ~40 MB either way
    // (allocator arenas of 7 threads, textures read lazily on first use: e.g. aggressor 209, 188,
    // 209, 209 MB); growth shows as a later load above the larger of the first two.
    for (const auto& [map, samples] : withMap)
      for (size_t i = 2; i < samples.size(); ++i) {
        const long warmLoaded = std::max(samples[0].residentKiB, samples[1].residentKiB);
        EXPECT_LE(samples[i].residentKiB - warmLoaded, kResidentSlackKiB)
            << map << " grows from loads 1-2 to load " << i + 1;
      }
  }
#endif
  for (const auto& [map, samples] : withMap) {
    std::printf("[soak] %s loaded:", map.c_str());
    for (const ProcessSample& s : samples) std::printf(" %ld KiB/%d thr", s.residentKiB, s.threads);
    std::printf("\n");
  }
}

}  // namespace
