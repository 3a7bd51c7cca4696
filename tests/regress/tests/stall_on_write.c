// pa_stall_on_write.so: preloaded into the engine by the CTest regress.capture_repeat
// (capture_repeat_test.sh). When the engine opens a file for writing whose path contains
// PA_STALL_ON_WRITE (e.g. "frame_0060", a screenshot), the call sleeps PA_STALL_MS milliseconds
// (default 4000) before it returns: the engine's wall clock jumps while the demo clock of a
// timedemo does not, as on a machine that another job stalls. A capture must not change. Each
// stall prints a line to stderr (the engine's log).
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/// fopen() of the C library; stalls after opening a matching path for writing (above).
FILE* fopen(const char* path, const char* mode) {
  static FILE* (*next)(const char*, const char*) = NULL;
  if (next == NULL) next = (FILE * (*)(const char*, const char*)) dlsym(RTLD_NEXT, "fopen");
  FILE* file = next != NULL ? next(path, mode) : NULL;
  const char* pattern = getenv("PA_STALL_ON_WRITE");
  if (file != NULL && pattern != NULL && *pattern != '\0' && path != NULL && mode != NULL &&
      strchr(mode, 'w') != NULL && strstr(path, pattern) != NULL) {
    const char* ms = getenv("PA_STALL_MS");
    const long stall = ms != NULL && *ms != '\0' ? strtol(ms, NULL, 10) : 4000;
    const struct timespec duration = {stall / 1000, (stall % 1000) * 1000000L};
    nanosleep(&duration, NULL);
    fprintf(stderr, "pa_stall_on_write: stalled %ld ms at %s\n", stall, path);
  }
  return file;
}
