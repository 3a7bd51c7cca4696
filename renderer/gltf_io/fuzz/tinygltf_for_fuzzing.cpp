// tinygltf's implementation compiled into the glTF fuzzer only (instrumented); see CMakeLists.txt,
// which also sets TINYGLTF_NO_STB_IMAGE(_WRITE) for every source of the harness.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
