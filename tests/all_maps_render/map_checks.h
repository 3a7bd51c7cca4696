#pragma once
// The checks of one map (spawn, render, plausible picture per integrator), the list of known
// problems that are expected to fail, and the results table.
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tests/all_maps_render/arena_info.h"
#include "tests/all_maps_render/image_stats.h"
#include "tests/all_maps_render/map_survey.h"

namespace pa::allmaps {

/// One integrator's render of a map, as far as the checks are concerned.
struct IntegratorOutcome {
  std::string integrator;              ///< "lightmap", "direct" or "path".
  bool rendered = false;               ///< pa-render succeeded and its outputs were read.
  ImageStats stats;                    ///< Valid when rendered: the judged picture (exposed by `exposure`).
  ImageStats unexposedStats;           ///< The same render at exposure 1 (the stock look), for the record.
  double exposure = 1.0;               ///< Gain of the judged picture.
  bool exposureAtMaxGain = false;      ///< The metered gain hit its upper clamp.
  double wallMilliseconds = 0.0;       ///< Load (the map's first picture only) + render, from pa-render's --stats.
  double renderMilliseconds = 0.0;     ///< Render only.
  std::vector<std::string> problems;   ///< Failed checks (empty = plausible).
  std::string expectedBecause;         ///< Non-empty: listed in the known problems with this reason.
  /// Failed and not listed as a known problem.
  bool unexpectedFailure() const { return !problems.empty() && expectedBecause.empty(); }
  /// Listed as a known problem but passed.
  bool unexpectedPass() const { return problems.empty() && !expectedBecause.empty(); }
};

/// Everything found about one map.
struct MapResult {
  std::string map;                         ///< "oa_dm1".
  std::string archive;                     ///< Archive the .bsp is read from.
  std::optional<ArenaEntry> arena;         ///< The map's entry in the game's arena lists (its first game type).
  MapSurvey survey;
  uint64_t triangles = 0;
  uint64_t lights = 0;                     ///< Lights pa-render created (entities, suns, surface lights).
  std::vector<std::string> mapProblems;    ///< Checks that concern the map, not one image (spawn, load).
  std::string mapExpectedBecause;          ///< Non-empty: the whole map ("*") is a known problem.
  std::vector<IntegratorOutcome> renders;  ///< One per integrator, in run order.
  /// Any failure not listed as a known problem.
  bool failed() const;
};

/// A known problem: map + integrator ("lightmap", "direct", "path" or "*") expected to fail, and why.
struct KnownProblem {
  std::string map;
  std::string integrator;
  std::string reason;
};

/// Parses the known-problems list: one "MAP INTEGRATOR REASON..." per line, '#' starts a comment.
/// Throws std::runtime_error naming `fileName` and the line for a malformed line.
std::vector<KnownProblem> parseKnownProblems(std::string_view text, const std::string& fileName);

/// The reason `map` rendered with `integrator` is expected to fail, if it is listed.
std::optional<std::string> knownProblemReason(const std::vector<KnownProblem>& known, std::string_view map,
                                              std::string_view integrator);

/// Writes the results as a Markdown table (one row per map) followed by the failures.
void writeMarkdownReport(std::ostream& out, const std::vector<MapResult>& results,
                         const PlausibilityThresholds& thresholds);

/// Writes the results as tab-separated values (one row per map and integrator), with a header.
void writeTsvReport(std::ostream& out, const std::vector<MapResult>& results);

}  // namespace pa::allmaps
