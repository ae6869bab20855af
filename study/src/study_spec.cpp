#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "sphfx/core/error.h"
#include "sphfx/study/study.h"

namespace sphfx::study {

using schema::makeSchema;
using schema::Object;
using schema::Range;
using schema::SchemaError;

namespace {

std::shared_ptr<const Object<Axis>> axisSchema() {
  return makeSchema<Axis>([](Object<Axis>& o) {
    o.text("path", &Axis::path, "", "Scene parameter, as for --set (e.g. fluid.spacing).")
        .anyJson("values", &Axis::values, Json::array(), "Values the parameter takes (JSON values).")
        .check([](const Axis& a, const Json&, const std::string& path) {
          if (a.path.empty())
            throw SchemaError(schema::childPath(path, "path"), "expected a scene parameter path");
          if (!a.values.is_array() || a.values.empty())
            throw SchemaError(schema::childPath(path, "values"), "expected a non-empty array of values");
        });
  });
}

std::shared_ptr<const Object<StudyCase>> caseSchema() {
  return makeSchema<StudyCase>([](Object<StudyCase>& o) {
    o.text("name", &StudyCase::name, "", "Case name (file and row labels).")
        .text("scene", &StudyCase::scene, "", "Scene file, relative to the study file.")
        .choice("validation", &StudyCase::validation, Validation::DamBreak,
                {{"dam_break", Validation::DamBreak},
                 {"hydrostatic", Validation::Hydrostatic},
                 {"poiseuille", Validation::Poiseuille},
                 {"taylor_green", Validation::TaylorGreen}},
                "Reference the runs are measured against.")
        .textList("set", &StudyCase::set, "Overrides for every run (path=value, as --set).")
        .list("axes", &StudyCase::axes, axisSchema(), 0, 8,
              "Parameter axes; the runs are their Cartesian product.")
        .text("convergence_axis", &StudyCase::convergenceAxis, "",
              "Axis (usually fluid.spacing) along which the observed order of convergence is computed.")
        .text("series_axis", &StudyCase::seriesAxis, "",
              "Axis whose values are the plot's series (e.g. solver.method).")
        .text("metric", &StudyCase::metric, "",
              "Error the runs are ranked by (the time-budget front, the plot): one of the validation's "
              "errors; empty: its primary one. front_self, the dam break's distance from the case's finest "
              "run along convergence_axis, ranks resolutions by their discretisation error alone.")
        .check([](const StudyCase& c, const Json&, const std::string& path) {
          if (c.name.empty()) throw SchemaError(schema::childPath(path, "name"), "expected a case name");
          if (c.scene.empty()) throw SchemaError(schema::childPath(path, "scene"), "expected a scene file");
          if (!c.metric.empty()) {
            const auto names = errorMetrics(c.validation);
            if (std::find(names.begin(), names.end(), c.metric) == names.end())
              throw SchemaError(
                  schema::childPath(path, "metric"),
                  fmt::format("expected one of {}, got \"{}\"", fmt::join(names, ", "), c.metric));
            if (c.metric == "front_self" && c.convergenceAxis.empty())
              throw SchemaError(schema::childPath(path, "metric"),
                                "front_self needs a convergence_axis (its finest run is the reference)");
          }
          for (const std::string* key : {&c.convergenceAxis, &c.seriesAxis}) {
            if (key->empty()) continue;
            bool found = false;
            for (const Axis& a : c.axes) found = found || a.path == *key;
            if (!found) throw SchemaError(path, "\"" + *key + "\" is not one of the case's axes");
          }
        });
  });
}

const Object<StudySpec>& studySchema() {
  static const auto schema = makeSchema<StudySpec>([](Object<StudySpec>& o) {
    o.text("name", &StudySpec::name, "study", "Study name.")
        .number("timeout", &StudySpec::timeoutSeconds, 600, "s", Range{0, 1e6, true, false},
                "Wall-clock limit per run; a run over it counts as failed.")
        .list("cases", &StudySpec::cases, caseSchema(), 1, 64, "Validation cases.");
  });
  return *schema;
}

}  // namespace

StudySpec loadStudy(const std::string& path) {
  StudySpec spec = schema::readDocument(studySchema(), schema::readJsonFile(path, "study"), path);
  spec.directory = std::filesystem::path(path).parent_path().string();
  return spec;
}

std::string toString(RunStatus s) {
  switch (s) {
    case RunStatus::Completed:
      return "completed";
    case RunStatus::StoppedCleanly:
      return "stopped-cleanly";
    case RunStatus::Failed:
      return "failed";
  }
  return "?";
}

}  // namespace sphfx::study
