// LD_PRELOAD shim for the sanitizer soak run of the real engine: makes dlclose() of the
// PathArena renderer module a no-op, so that LeakSanitizer, which symbolizes at exit, can still
// name the module's frames (a dlclose()d module's frames print as "<unknown module>").
// Everything else is passed to the real dlclose.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <link.h>
#include <string.h>

int dlclose(void* handle) {
  static int (*realDlclose)(void*);
  if (realDlclose == NULL) realDlclose = (int (*)(void*))dlsym(RTLD_NEXT, "dlclose");
  struct link_map* map = NULL;
  if (handle != NULL && dlinfo(handle, RTLD_DI_LINKMAP, &map) == 0 && map != NULL &&
      map->l_name != NULL && strstr(map->l_name, "renderer_pathtracer") != NULL)
    return 0;
  return realDlclose(handle);
}
