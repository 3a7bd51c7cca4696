/* stb_image compiled into the image fuzzer only (instrumented); see CMakeLists.txt. */
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
