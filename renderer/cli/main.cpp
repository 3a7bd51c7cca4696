// pa-render: renders a scene file to PNG (and EXR). See `pa-render --help`.
#include <cstdio>
#include <string_view>
#include <vector>

#include "renderer/cli/cli_options.h"
#include "renderer/cli/render_job.h"

int main(int argc, char** argv) {
  using namespace pa::cli;
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  const ParseResult parsed = parseCommandLine(args);
  switch (parsed.status) {
    case ParseStatus::Help:
      std::fputs(usageText("pa-render").c_str(), stdout);
      return kExitOk;
    case ParseStatus::Error:
      std::fprintf(stderr, "pa-render: %s\nUsage: pa-render SCENE -o OUT.png [options]; see pa-render --help\n",
                   parsed.message.c_str());
      return kExitUsage;
    case ParseStatus::Ok:
      break;
  }
  return runRenderJob(parsed.options, stderr);
}
