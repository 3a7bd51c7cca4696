#pragma once
// The ioquake3 renderer-module interface (REF_API_VERSION 8, ioquake3 commit 70d07d9 as shipped
// by Debian bookworm), declared from the documented facts in /work/shared/ioq3-renderer-abi.md:
// member order, types, sizes. Every size and offset we rely on is pinned by a static_assert.
// Plain C layout: this header is the only place where engine types are spelled out.
#include <cstddef>
#include <cstdint>

namespace q3abi {

inline constexpr int kRefApiVersion = 8;
inline constexpr int kMaxStringChars = 1024;
inline constexpr int kBigInfoString = 8192;
inline constexpr int kMaxMapAreaBytes = 32;
inline constexpr int kMaxQPath = 64;
inline constexpr int kGlyphsPerFont = 256;
inline constexpr int kMaxDlights = 32;
inline constexpr int kMaxRefEntities = 1023;

using qboolean = int;   ///< An int-sized enum in C: 0 false, 1 true.
using qhandle_t = int;  ///< Index into a renderer table; 0 = none/default.
using vec3_t = float[3];
using byte = unsigned char;

/// Print levels of refimport_t::Printf.
enum PrintLevel : int { PRINT_ALL = 0, PRINT_DEVELOPER = 1, PRINT_WARNING = 2, PRINT_ERROR = 3 };
/// Error levels of refimport_t::Error.
enum ErrorLevel : int { ERR_FATAL = 0, ERR_DROP = 1, ERR_SERVERDISCONNECT = 2, ERR_DISCONNECT = 3 };
/// Cvar flags we use.
enum CvarFlags : int { CVAR_ARCHIVE = 0x1, CVAR_LATCH = 0x20, CVAR_CHEAT = 0x200 };
/// Cmd_ExecuteText "when".
enum CbufExec : int { EXEC_NOW = 0, EXEC_INSERT = 1, EXEC_APPEND = 2 };
/// BeginFrame's stereo selector.
enum StereoFrame : int { STEREO_CENTER = 0, STEREO_LEFT = 1, STEREO_RIGHT = 2 };

/// refEntity_t::reType.
enum RefEntityType : int {
  RT_MODEL = 0, RT_POLY, RT_SPRITE, RT_BEAM, RT_RAIL_CORE, RT_RAIL_RINGS, RT_LIGHTNING,
  RT_PORTALSURFACE, RT_MAX_REF_ENTITY_TYPE
};
/// refEntity_t::renderfx bits.
enum RenderFx : int {
  RF_MINLIGHT = 0x0001, RF_THIRD_PERSON = 0x0002, RF_FIRST_PERSON = 0x0004, RF_DEPTHHACK = 0x0008,
  RF_CROSSHAIR = 0x0010, RF_NOSHADOW = 0x0040, RF_LIGHTING_ORIGIN = 0x0080,
  RF_SHADOW_PLANE = 0x0100, RF_WRAP_FRAMES = 0x0200
};
/// refdef_t::rdflags bits.
enum RefdefFlags : int { RDF_NOWORLDMODEL = 0x0001, RDF_HYPERSPACE = 0x0004 };

/// A vertex of AddPolyToScene.
struct polyVert_t {
  vec3_t xyz;
  float st[2];
  byte modulate[4];
};

/// One entity of a scene.
struct refEntity_t {
  int reType;
  int renderfx;
  qhandle_t hModel;
  vec3_t lightingOrigin;
  float shadowPlane;
  vec3_t axis[3];
  qboolean nonNormalizedAxes;
  float origin[3];
  int frame;
  float oldorigin[3];
  int oldframe;
  float backlerp;
  int skinNum;
  qhandle_t customSkin;
  qhandle_t customShader;
  byte shaderRGBA[4];
  float shaderTexCoord[2];
  float shaderTime;
  float radius;
  float rotation;
};

/// One 3D view.
struct refdef_t {
  int x, y, width, height;
  float fov_x, fov_y;
  vec3_t vieworg;
  vec3_t viewaxis[3];
  int time;
  int rdflags;
  byte areamask[kMaxMapAreaBytes];
  char text[8][32];
};

/// What the renderer tells the engine about the display.
struct glconfig_t {
  char renderer_string[kMaxStringChars];
  char vendor_string[kMaxStringChars];
  char version_string[kMaxStringChars];
  char extensions_string[kBigInfoString];
  int maxTextureSize;
  int numTextureUnits;
  int colorBits, depthBits, stencilBits;
  int driverType;              ///< 0 = GLDRV_ICD
  int hardwareType;            ///< 0 = GLHW_GENERIC
  qboolean deviceSupportsGamma;
  int textureCompression;      ///< 0 = TC_NONE
  qboolean textureEnvAddAvailable;
  int vidWidth, vidHeight;
  float windowAspect;
  int displayFrequency;
  qboolean isFullscreen;
  qboolean stereoEnabled;
  qboolean smpActive;
};

/// A tag's placement (LerpTag).
struct orientation_t {
  vec3_t origin;
  vec3_t axis[3];
};

/// One clipped decal fragment (MarkFragments).
struct markFragment_t {
  int firstPoint;
  int numPoints;
};

/// One glyph of a pre-rendered font.
struct glyphInfo_t {
  int height, top, bottom, pitch, xSkip, imageWidth, imageHeight;
  float s, t, s2, t2;
  qhandle_t glyph;
  char shaderName[32];
};

/// A pre-rendered font (RegisterFont).
struct fontInfo_t {
  glyphInfo_t glyphs[kGlyphsPerFont];
  float glyphScale;
  char name[kMaxQPath];
};

/// The engine's console variable (read-only for us except through Cvar_Set).
struct cvar_t {
  char* name;
  char* string;
  char* resetString;
  char* latchedString;
  int flags;
  qboolean modified;
  int modificationCount;
  float value;
  int integer;
  qboolean validate;
  qboolean integral;
  float min;
  float max;
  char* description;
  cvar_t* next;
  cvar_t* prev;
  cvar_t* hashNext;
  cvar_t* hashPrev;
  int hashIndex;
};

/// Functions the engine gives the renderer.
struct refimport_t {
  void (*Printf)(int printLevel, const char* fmt, ...);
  void (*Error)(int errorLevel, const char* fmt, ...);   ///< Does not return (longjmp).
  int (*Milliseconds)();
  void* (*Hunk_Alloc)(int size, int preference);
  void* (*Hunk_AllocateTempMemory)(int size);
  void (*Hunk_FreeTempMemory)(void* block);
  void* (*Malloc)(int bytes);
  void (*Free)(void* buf);
  cvar_t* (*Cvar_Get)(const char* name, const char* value, int flags);
  void (*Cvar_Set)(const char* name, const char* value);
  void (*Cvar_SetValue)(const char* name, float value);
  void (*Cvar_CheckRange)(cvar_t* cv, float minVal, float maxVal, qboolean shouldBeIntegral);
  void (*Cvar_SetDescription)(cvar_t* cv, const char* description);
  int (*Cvar_VariableIntegerValue)(const char* name);
  void (*Cmd_AddCommand)(const char* name, void (*cmd)());
  void (*Cmd_RemoveCommand)(const char* name);
  int (*Cmd_Argc)();
  char* (*Cmd_Argv)(int i);
  void (*Cmd_ExecuteText)(int exec_when, const char* text);
  byte* (*CM_ClusterPVS)(int cluster);
  void (*CM_DrawDebugSurface)(void (*drawPoly)(int color, int numPoints, float* points));
  int (*FS_FileIsInPAK)(const char* name, int* pChecksum);
  long (*FS_ReadFile)(const char* name, void** buf);
  void (*FS_FreeFile)(void* buf);
  char** (*FS_ListFiles)(const char* name, const char* extension, int* numfilesfound);
  void (*FS_FreeFileList)(char** filelist);
  void (*FS_WriteFile)(const char* qpath, const void* buffer, int size);
  qboolean (*FS_FileExists)(const char* file);
  void (*CIN_UploadCinematic)(int handle);
  int (*CIN_PlayCinematic)(const char* arg0, int xpos, int ypos, int width, int height, int bits);
  int (*CIN_RunCinematic)(int handle);
  void (*CL_WriteAVIVideoFrame)(const byte* buffer, int size);
  void (*IN_Init)(void* windowData);
  void (*IN_Shutdown)();
  void (*IN_Restart)();
  long (*ftol)(float f);
  void (*Sys_SetEnv)(const char* name, const char* value);
  void (*Sys_GLimpSafeInit)();
  void (*Sys_GLimpInit)();
  qboolean (*Sys_LowPhysicalMemory)();
};

/// Functions the renderer gives the engine (GetRefAPI's result).
struct refexport_t {
  void (*Shutdown)(qboolean destroyWindow);
  void (*BeginRegistration)(glconfig_t* config);
  qhandle_t (*RegisterModel)(const char* name);
  qhandle_t (*RegisterSkin)(const char* name);
  qhandle_t (*RegisterShader)(const char* name);
  qhandle_t (*RegisterShaderNoMip)(const char* name);
  void (*LoadWorld)(const char* name);
  void (*SetWorldVisData)(const byte* vis);
  void (*EndRegistration)();
  void (*ClearScene)();
  void (*AddRefEntityToScene)(const refEntity_t* re);
  void (*AddPolyToScene)(qhandle_t hShader, int numVerts, const polyVert_t* verts, int num);
  int (*LightForPoint)(vec3_t point, vec3_t ambientLight, vec3_t directedLight, vec3_t lightDir);
  void (*AddLightToScene)(const vec3_t org, float intensity, float r, float g, float b);
  void (*AddAdditiveLightToScene)(const vec3_t org, float intensity, float r, float g, float b);
  void (*RenderScene)(const refdef_t* fd);
  void (*SetColor)(const float* rgba);
  void (*DrawStretchPic)(float x, float y, float w, float h, float s1, float t1, float s2,
                         float t2, qhandle_t hShader);
  void (*DrawStretchRaw)(int x, int y, int w, int h, int cols, int rows, const byte* data,
                         int client, qboolean dirty);
  void (*UploadCinematic)(int w, int h, int cols, int rows, const byte* data, int client,
                          qboolean dirty);
  void (*BeginFrame)(int stereoFrame);
  void (*EndFrame)(int* frontEndMsec, int* backEndMsec);
  int (*MarkFragments)(int numPoints, const vec3_t* points, const vec3_t projection,
                       int maxPoints, vec3_t pointBuffer, int maxFragments,
                       markFragment_t* fragmentBuffer);
  int (*LerpTag)(orientation_t* tag, qhandle_t model, int startFrame, int endFrame,
                 float frac, const char* tagName);
  void (*ModelBounds)(qhandle_t model, vec3_t mins, vec3_t maxs);
  void (*RegisterFont)(const char* fontName, int pointSize, fontInfo_t* font);
  void (*RemapShader)(const char* oldShader, const char* newShader, const char* offsetTime);
  qboolean (*GetEntityToken)(char* buffer, int size);
  qboolean (*inPVS)(const vec3_t p1, const vec3_t p2);
  /// Called by the client as (width, height, ...) although the header names them (h, w).
  void (*TakeVideoFrame)(int width, int height, byte* captureBuffer, byte* encodeBuffer,
                         qboolean motionJpeg);
};

// ---- Layout checks: measured on x86-64 from the 70d07d9 headers (see the ABI facts doc). ----
static_assert(sizeof(qboolean) == 4 && sizeof(qhandle_t) == 4 && sizeof(vec3_t) == 12);
static_assert(sizeof(polyVert_t) == 24);
static_assert(offsetof(polyVert_t, xyz) == 0 && offsetof(polyVert_t, st) == 12 &&
              offsetof(polyVert_t, modulate) == 20);
static_assert(sizeof(refEntity_t) == 140);
static_assert(offsetof(refEntity_t, reType) == 0 && offsetof(refEntity_t, renderfx) == 4 &&
              offsetof(refEntity_t, hModel) == 8 && offsetof(refEntity_t, lightingOrigin) == 12 &&
              offsetof(refEntity_t, shadowPlane) == 24 && offsetof(refEntity_t, axis) == 28 &&
              offsetof(refEntity_t, nonNormalizedAxes) == 64 && offsetof(refEntity_t, origin) == 68 &&
              offsetof(refEntity_t, frame) == 80 && offsetof(refEntity_t, oldorigin) == 84 &&
              offsetof(refEntity_t, oldframe) == 96 && offsetof(refEntity_t, backlerp) == 100 &&
              offsetof(refEntity_t, skinNum) == 104 && offsetof(refEntity_t, customSkin) == 108 &&
              offsetof(refEntity_t, customShader) == 112 &&
              offsetof(refEntity_t, shaderRGBA) == 116 &&
              offsetof(refEntity_t, shaderTexCoord) == 120 &&
              offsetof(refEntity_t, shaderTime) == 128 && offsetof(refEntity_t, radius) == 132 &&
              offsetof(refEntity_t, rotation) == 136);
static_assert(sizeof(refdef_t) == 368);
static_assert(offsetof(refdef_t, x) == 0 && offsetof(refdef_t, y) == 4 &&
              offsetof(refdef_t, width) == 8 && offsetof(refdef_t, height) == 12 &&
              offsetof(refdef_t, fov_x) == 16 && offsetof(refdef_t, fov_y) == 20 &&
              offsetof(refdef_t, vieworg) == 24 && offsetof(refdef_t, viewaxis) == 36 &&
              offsetof(refdef_t, time) == 72 && offsetof(refdef_t, rdflags) == 76 &&
              offsetof(refdef_t, areamask) == 80 && offsetof(refdef_t, text) == 112);
static_assert(sizeof(glconfig_t) == 11332);
static_assert(offsetof(glconfig_t, vendor_string) == 1024 &&
              offsetof(glconfig_t, version_string) == 2048 &&
              offsetof(glconfig_t, extensions_string) == 3072 &&
              offsetof(glconfig_t, maxTextureSize) == 11264 &&
              offsetof(glconfig_t, vidWidth) == 11304 && offsetof(glconfig_t, vidHeight) == 11308 &&
              offsetof(glconfig_t, windowAspect) == 11312 &&
              offsetof(glconfig_t, displayFrequency) == 11316 &&
              offsetof(glconfig_t, isFullscreen) == 11320 &&
              offsetof(glconfig_t, stereoEnabled) == 11324 &&
              offsetof(glconfig_t, smpActive) == 11328);
static_assert(sizeof(orientation_t) == 48 && offsetof(orientation_t, axis) == 12);
static_assert(sizeof(markFragment_t) == 8 && offsetof(markFragment_t, numPoints) == 4);
static_assert(sizeof(glyphInfo_t) == 80 && offsetof(glyphInfo_t, glyph) == 44 &&
              offsetof(glyphInfo_t, shaderName) == 48);
static_assert(sizeof(fontInfo_t) == 20548 && offsetof(fontInfo_t, glyphScale) == 20480 &&
              offsetof(fontInfo_t, name) == 20484);
static_assert(sizeof(cvar_t) == 120);
static_assert(offsetof(cvar_t, string) == 8 && offsetof(cvar_t, resetString) == 16 &&
              offsetof(cvar_t, latchedString) == 24 && offsetof(cvar_t, flags) == 32 &&
              offsetof(cvar_t, modified) == 36 && offsetof(cvar_t, modificationCount) == 40 &&
              offsetof(cvar_t, value) == 44 && offsetof(cvar_t, integer) == 48 &&
              offsetof(cvar_t, validate) == 52 && offsetof(cvar_t, integral) == 56 &&
              offsetof(cvar_t, min) == 60 && offsetof(cvar_t, max) == 64 &&
              offsetof(cvar_t, description) == 72 && offsetof(cvar_t, next) == 80);
static_assert(sizeof(refexport_t) == 240 && offsetof(refexport_t, TakeVideoFrame) == 29 * 8);
static_assert(offsetof(refexport_t, RenderScene) == 15 * 8 &&
              offsetof(refexport_t, EndFrame) == 21 * 8);
static_assert(sizeof(refimport_t) == 320 && offsetof(refimport_t, Sys_LowPhysicalMemory) == 39 * 8);
static_assert(offsetof(refimport_t, FS_ReadFile) == 22 * 8 && offsetof(refimport_t, IN_Init) == 32 * 8);

}  // namespace q3abi
