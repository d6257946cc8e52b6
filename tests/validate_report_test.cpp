// `raycoh validate`'s printout says what kind each figure is: a GPU's rows are "Measured speeds", GPGPU-Sim's
// "Simulated speeds", the model's "The GPU timing model"; a simulated NoOpt is never called measured.
#include "harness/validate/validate_report.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace raycoh {
namespace {

std::vector<ValidateRow> sibenik_noopt(const std::string& kind) {
  ValidateRow v;
  v.table = "table1";
  v.row = "noopt";
  v.paper_scene = "Sibenik";
  v.paper_row = "NoOpt";
  v.paper_mray_s = 154.7;
  v.paper_ratio = 1;
  v.kind = kind;
  if (kind == "modeled") {
    v.modeled_mray_s = 300, v.modeled_ratio = 1;
  } else {
    v.measured_mray_s = 300, v.measured_ratio = 1;
  }
  v.provenance.device = kind == "simulated" ? "simulated: GPGPU-Sim" : "NVIDIA H200";
  return {v};
}

TEST(ValidateReport, SaysWhatKindEachFigureIs) {
  const std::string measured = validate_report("tile", 16, 16, sibenik_noopt("measured"));
  EXPECT_NE(measured.find("## Measured speeds beside the paper"), std::string::npos) << measured;
  EXPECT_NE(measured.find("MEASURED on NVIDIA H200"), std::string::npos) << measured;
  EXPECT_NE(measured.find("MRay/s measured on another GPU"), std::string::npos) << measured;

  const std::string simulated = validate_report("tile", 16, 16, sibenik_noopt("simulated"));
  EXPECT_NE(simulated.find("## Simulated speeds (GPGPU-Sim, not hardware) beside the paper"), std::string::npos)
      << simulated;
  EXPECT_NE(simulated.find("SIMULATED on simulated: GPGPU-Sim"), std::string::npos) << simulated;
  // "measured" only of the paper's own figures.
  std::string ours = simulated;
  const std::string paper = "Paper: Liu et al. 2024, measured on an RTX 3060.";
  ASSERT_NE(ours.find(paper), std::string::npos) << simulated;
  ours.erase(ours.find(paper), paper.size());
  EXPECT_EQ(ours.find("easured"), std::string::npos) << simulated;

  const std::string modeled = validate_report("tile", 16, 16, sibenik_noopt("modeled"));
  EXPECT_NE(modeled.find("## The GPU timing model beside the paper"), std::string::npos) << modeled;
  EXPECT_NE(modeled.find("MODELED, not measured"), std::string::npos) << modeled;
}

}  // namespace
}  // namespace raycoh
