// pa_fixed_rand.so: preloaded into the engine for captures (LD_PRELOAD, tests/regress/README.md,
// "Repeatable game frames"). The engine seeds the C library's rand() from /dev/urandom when it
// starts, and the game's native cgame draws its effects from rand() (smoke puffs, the HUD head's
// turns, brass, gibs), so two runs of one demo differ there whatever the renderer. This srand()
// replaces every seed with PA_FIXED_RAND_SEED (when set), which makes the game's whole rand()
// sequence repeat run to run.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdlib.h>

/// srand() of the C library, called with PA_FIXED_RAND_SEED instead of `seed` when that is set.
void srand(unsigned seed) {
  static void (*next)(unsigned) = NULL;
  if (next == NULL) next = (void (*)(unsigned))dlsym(RTLD_NEXT, "srand");
  const char* fixed = getenv("PA_FIXED_RAND_SEED");
  if (fixed != NULL && *fixed != '\0') seed = (unsigned)strtoul(fixed, NULL, 10);
  if (next != NULL) next(seed);
}
