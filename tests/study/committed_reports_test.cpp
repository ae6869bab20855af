// The validation reports committed under docs/ were generated from the study and suite files shipped
// now: each states the digest of its runs' resolved scenes, and a changed scene, axis, override or
// schema default changes the digest. Regenerate a stale one with the command the failure prints.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "sphfx/study/stability.h"
#include "sphfx/study/study.h"

using namespace sphfx::study;

namespace {

const std::string kDir = SPHFX_SOURCE_DIR;

std::string committedDigest(const std::string& report) {
  std::ifstream in(kDir + "/" + report);
  std::stringstream text;
  text << in.rdbuf();
  std::smatch m;
  const std::string s = text.str();
  if (!std::regex_search(s, m, std::regex("<!-- inputs digest: ([0-9a-f]{16}) -->"))) return "(none)";
  return m[1];
}

}  // namespace

TEST(CommittedReports, QuickStudyMatchesTheShippedStudy) {
  const std::string now = studyInputsDigest(loadStudy(kDir + "/studies/quick.json"));
  EXPECT_EQ(committedDigest("docs/quick-study/report.md"), now)
      << "stale: run build/cli/sphfx study studies/quick.json -o docs/quick-study";
}

TEST(CommittedReports, TaylorGreenStudyMatchesTheShippedStudy) {
  const std::string now = studyInputsDigest(loadStudy(kDir + "/studies/taylor_green.json"));
  EXPECT_EQ(committedDigest("docs/taylor-green-study/report.md"), now)
      << "stale: run build/cli/sphfx study studies/taylor_green.json -o docs/taylor-green-study";
}

TEST(CommittedReports, StabilityReportMatchesTheShippedSuite) {
  const StabilitySuite suite = loadStabilitySuite(kDir + "/studies/stability.json");
  EXPECT_EQ(committedDigest("docs/stability-full/stability.md"), stabilityInputsDigest(suite, false))
      << "stale: run build/cli/sphfx stability -o docs/stability-full";
}

TEST(CommittedReports, TheDigestSeesAChangedDefault) {
  StudySpec spec = loadStudy(kDir + "/studies/quick.json");
  const std::string before = studyInputsDigest(spec);
  spec.cases.front().set.push_back("fluid.rest_density=999");
  EXPECT_NE(studyInputsDigest(spec), before);
}
