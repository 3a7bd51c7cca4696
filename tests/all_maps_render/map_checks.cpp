// Known-problems list and the Markdown / TSV results tables.
#include "tests/all_maps_render/map_checks.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace pa::allmaps {
namespace {

std::string format(const char* pattern, double value) {
  char text[32];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

std::string floorText(const SpawnPoint& s) {
  return s.floorDistance ? format("%.0f", *s.floorDistance) : std::string("none");
}

std::string spawnText(const MapResult& r) {
  if (!r.survey.spawn) return "none";
  const glm::vec3& o = r.survey.spawn->origin;
  char text[96];
  std::snprintf(text, sizeof text, "%u: (%.0f %.0f %.0f)", r.survey.spawn->cameraIndex, o.x, o.y, o.z);
  return text;
}

std::string originText(const glm::vec3& o) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.0f %.0f %.0f)", o.x, o.y, o.z);
  return text;
}

/// The spawn classes a family starts its players at, as the notes name them.
std::string familyClasses(SpawnFamily family) {
  return family == SpawnFamily::Team ? "team_CTF_redplayer/blueplayer (then team_CTF_redspawn/bluespawn)"
                                     : "info_player_deathmatch/start";
}

/// "`ctf` (first game type in scripts/arenas.txt)" or "" without an arena entry.
std::string gameTypeText(const MapResult& r) {
  if (!r.arena) return "";
  return "`" + (r.arena->gameType.empty() ? std::string("?") : r.arena->gameType) + "` (first game type in " +
         r.arena->file + ")";
}

/// Why the rendered spawn is not the first player spawn (empty when it is).
std::string spawnChoiceNote(const MapResult& r) {
  const MapSurvey& s = r.survey;
  if (!s.spawn || !s.firstSpawn) return "";
  if (!s.spawn->standsOnFloor())
    return "no player spawn stands on a floor (floor within " + format("%.0f", kMaxSpawnFloorDistance) +
           " units): the first, " + s.firstSpawn->cameraName + " (floor " + floorText(*s.firstSpawn) + "), is rendered";
  if (s.spawn->cameraName == s.firstSpawn->cameraName) return "";
  const std::string first = "the first player spawn is " + s.firstSpawn->cameraName + " at " +
                            originText(s.firstSpawn->origin) + " with floor " + floorText(*s.firstSpawn) + " below";
  const std::string rendered = s.spawn->cameraName + " at " + originText(s.spawn->origin) + " (floor " +
                               floorText(*s.spawn) + " below) is rendered: ";
  if (s.family && s.familyFound)
    return rendered + "the map's game type is " + gameTypeText(r) + ", whose players start at " +
           familyClasses(*s.family) + "; " + first;
  const std::string noFamily = s.family ? "no " + familyClasses(*s.family) + " spawn of its game type " +
                                              gameTypeText(r) + " stands on a floor; "
                                        : "";
  return rendered + noFamily + std::to_string(s.spawnsWithoutFloor) + " earlier spawn(s) stand on no floor; " + first;
}

std::string joined(const std::vector<std::string>& items, std::string_view separator) {
  std::string out;
  for (const std::string& item : items) {
    if (!out.empty()) out += separator;
    out += item;
  }
  return out;
}

/// "ok", "FAIL", "known" (failed as expected) or "XPASS" (known problem that passed).
std::string verdictWord(const IntegratorOutcome& o) {
  if (o.unexpectedFailure()) return "FAIL";
  if (o.unexpectedPass()) return "XPASS";
  return o.problems.empty() ? "ok" : "known";
}

}  // namespace

bool MapResult::failed() const {
  return (!mapProblems.empty() && mapExpectedBecause.empty()) ||
         std::any_of(renders.begin(), renders.end(), [](const IntegratorOutcome& o) { return o.unexpectedFailure(); });
}

std::vector<KnownProblem> parseKnownProblems(std::string_view text, const std::string& fileName) {
  std::vector<KnownProblem> known;
  std::istringstream lines{std::string(text)};
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    KnownProblem problem;
    if (!(fields >> problem.map)) continue;   // blank or comment-only line
    fields >> problem.integrator;
    std::getline(fields >> std::ws, problem.reason);
    while (!problem.reason.empty() && std::isspace(static_cast<unsigned char>(problem.reason.back())))
      problem.reason.pop_back();
    if (problem.integrator != "lightmap" && problem.integrator != "direct" && problem.integrator != "path" &&
        problem.integrator != "*")
      throw std::runtime_error(fileName + ":" + std::to_string(number) +
                               ": expected MAP (lightmap|direct|path|*) REASON, got \"" + line + "\"");
    if (problem.reason.empty())
      throw std::runtime_error(fileName + ":" + std::to_string(number) + ": a known problem needs a reason");
    known.push_back(std::move(problem));
  }
  return known;
}

std::optional<std::string> knownProblemReason(const std::vector<KnownProblem>& known, std::string_view map,
                                              std::string_view integrator) {
  for (const KnownProblem& k : known)
    if (k.map == map && (k.integrator == "*" || k.integrator == integrator)) return k.reason;
  return std::nullopt;
}

void writeMarkdownReport(std::ostream& out, const std::vector<MapResult>& results,
                         const PlausibilityThresholds& thresholds) {
  std::vector<std::string> integrators;
  for (const MapResult& r : results)
    for (const IntegratorOutcome& o : r.renders)
      if (std::find(integrators.begin(), integrators.end(), o.integrator) == integrators.end())
        integrators.push_back(o.integrator);

  out << "Plausible: world (not sky) mean luma >= " << format("%.3f", thresholds.minMeanLuma) << ", black world pixels (luma < "
      << format("%.3f", thresholds.blackLuma) << ", sky excluded) <= "
      << format("%.0f%%", 100 * thresholds.maxBlackFraction)
      << ", sky/void pixels <= " << format("%.0f%%", 100 * thresholds.maxSkyFraction)
      << ", spawn eye in a leaf of the level (PVS cluster >= 0).\n\n";
  out << "| map | tris | lights | spawn (camera: origin) | floor | cluster |";
  for (const std::string& i : integrators) out << ' ' << i << " gain | lum | lum x1 | black | sky | ms | verdict |";
  out << "\n|---|--:|--:|---|--:|--:|";
  for (size_t i = 0; i < integrators.size(); ++i) out << "--:|--:|--:|--:|--:|--:|---|";
  out << '\n';
  for (const MapResult& r : results) {
    out << "| " << r.map << " | " << r.triangles << " | " << r.lights << " | " << spawnText(r) << " | "
        << (r.survey.spawn ? floorText(*r.survey.spawn) : "-") << " | " << r.survey.eyeCluster << " |";
    for (const std::string& i : integrators) {
      const auto o = std::find_if(r.renders.begin(), r.renders.end(),
                                  [&](const IntegratorOutcome& x) { return x.integrator == i; });
      if (o == r.renders.end() || !o->rendered) {
        out << " - | - | - | - | - | - | " << (o == r.renders.end() ? "not run" : verdictWord(*o)) << " |";
        continue;
      }
      out << ' ' << format("%.2f", o->exposure) << (o->exposureAtMaxGain ? " (max)" : "") << " | "
          << format("%.3f", o->stats.meanLuma) << " | " << format("%.3f", o->unexposedStats.meanLuma) << " | "
          << format("%.1f%%", 100 * o->stats.blackFraction)
          << " | " << format("%.1f%%", 100 * o->stats.skyFraction) << " | " << format("%.0f", o->wallMilliseconds)
          << " | " << verdictWord(*o) << " |";
    }
    out << '\n';
  }

  std::ostringstream failures, known, passes, spawnChoices;
  for (const MapResult& r : results) {
    if (const std::string note = spawnChoiceNote(r); !note.empty()) spawnChoices << "- " << r.map << ": " << note << '\n';
    for (const std::string& p : r.mapProblems)
      (r.mapExpectedBecause.empty() ? failures : known)
          << "- " << r.map << ": " << p
          << (r.mapExpectedBecause.empty() ? std::string() : " (known: " + r.mapExpectedBecause + ")") << '\n';
    for (const IntegratorOutcome& o : r.renders) {
      if (o.unexpectedFailure()) failures << "- " << r.map << " " << o.integrator << ": " << joined(o.problems, "; ") << '\n';
      else if (!o.problems.empty())
        known << "- " << r.map << " " << o.integrator << ": " << joined(o.problems, "; ") << " (known: "
              << o.expectedBecause << ")\n";
      else if (o.unexpectedPass())
        passes << "- " << r.map << " " << o.integrator << " passes although listed as a known problem ("
               << o.expectedBecause << "): remove it from the list\n";
    }
  }
  out << "\nSpawn choices (the first spawn that stands on a floor of the classes the map's first game type starts "
         "its players at; \"floor\" = units from the origin down to the floor):\n"
      << (spawnChoices.str().empty() ? "- every map: its first player spawn\n" : spawnChoices.str());
  out << "\nFailures:\n" << (failures.str().empty() ? "- none\n" : failures.str());
  out << "\nKnown problems (expected to fail):\n" << (known.str().empty() ? "- none\n" : known.str());
  if (!passes.str().empty()) out << "\nKnown problems that no longer fail:\n" << passes.str();
}

void writeTsvReport(std::ostream& out, const std::vector<MapResult>& results) {
  out << "map\tarchive\ttriangles\tlights\tlight_entities\tcamera\tcamera_index\torigin_x\torigin_y\torigin_z\tfloor_distance\tfirst_spawn\tgame_type\tcluster"
         "\tintegrator\texposure\texposure_at_max\tmean_luma\tblack_fraction\tsky_fraction\tmean_luma_x1\tblack_fraction_x1\twall_ms\trender_ms\tverdict\tproblems\n";
  for (const MapResult& r : results) {
    const SpawnPoint spawn = r.survey.spawn.value_or(SpawnPoint{});
    for (const IntegratorOutcome& o : r.renders) {
      std::vector<std::string> problems = r.mapProblems;
      problems.insert(problems.end(), o.problems.begin(), o.problems.end());
      out << r.map << '\t' << r.archive << '\t' << r.triangles << '\t' << r.lights << '\t' << r.survey.lightEntities
          << '\t' << spawn.cameraName << '\t' << spawn.cameraIndex << '\t' << spawn.origin.x << '\t' << spawn.origin.y
          << '\t' << spawn.origin.z << '\t' << floorText(spawn) << '\t'
          << (r.survey.firstSpawn ? r.survey.firstSpawn->cameraName : std::string()) << '\t'
          << (r.arena ? r.arena->gameType : std::string()) << '\t' << r.survey.eyeCluster
          << '\t' << o.integrator << '\t' << format("%.4f", o.exposure) << '\t' << (o.exposureAtMaxGain ? 1 : 0) << '\t'
          << format("%.4f", o.stats.meanLuma) << '\t' << format("%.4f", o.stats.blackFraction) << '\t'
          << format("%.4f", o.stats.skyFraction) << '\t' << format("%.4f", o.unexposedStats.meanLuma) << '\t'
          << format("%.4f", o.unexposedStats.blackFraction) << '\t' << format("%.0f", o.wallMilliseconds) << '\t'
          << format("%.0f", o.renderMilliseconds) << '\t' << verdictWord(o) << '\t' << joined(problems, "; ") << '\n';
    }
  }
}

}  // namespace pa::allmaps
