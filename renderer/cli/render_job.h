#pragma once
// pa-render's work after parsing: import, commit, render with accumulation, write images.
#include <cstdio>

#include "renderer/cli/cli_options.h"

namespace pa::cli {

/// Process exit codes of pa-render.
enum ExitCode : int { kExitOk = 0, kExitFailure = 1, kExitUsage = 2 };

/// Runs a parsed command line; messages go to `log` (stderr). Returns the exit code.
int runRenderJob(const CliOptions& options, std::FILE* log);

/// Image size from the options and the camera's preferred aspect (0 = none):
/// both given -> as is; one given -> the other follows the aspect; none -> width 640.
void resolveImageSize(const CliOptions& options, float cameraAspect, uint32_t& width, uint32_t& height);

}  // namespace pa::cli
