#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.hpp"
#include "study/study_spec.hpp"

namespace test_study_spec {

using namespace settle;
namespace fs = std::filesystem;

fs::path write_study(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("settle_study_spec_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

const std::string kBase = std::string("[study]\nbase = \"") + SETTLE_SOURCE_DIR + "/cases/towed_sphere.toml\"\n";

std::string refusal(const std::string& text) {
  try {
    study::expand(study::read_study(write_study("bad.toml", text)));
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(StudySpec, ExpandsTheProductInFileOrderTheLastFastest) {
  const auto spec = study::read_study(write_study("product.toml", kBase + R"(
[vary]
reynolds = { from = 10.0, to = 1000.0, count = 3, spacing = "log" }
numerics.cells_per_diameter = { from = 6, to = 10, step = 2 }
)"));
  const auto cases = study::expand(spec);
  ASSERT_EQ(cases.size(), 9u);
  EXPECT_EQ(study::describe_inputs(cases[0].inputs), "reynolds = 10.0, numerics.cells_per_diameter = 6");
  EXPECT_EQ(study::describe_inputs(cases[5].inputs), "reynolds = 100.0, numerics.cells_per_diameter = 10");
  EXPECT_EQ(cases[8].values.real("numerics.cells_per_diameter"), 10.0);
  // Re = U d / nu with d = 1 mm and nu = 1e-6 m^2/s (the base case): 1000 -> 1 m/s.
  EXPECT_NEAR(cases[8].values.reals("particle.towing_velocity")[2], -1.0, 1e-12);
}

TEST(StudySpec, AnInlineBaseAndAnEnsembleGiveOneCaseAnOrientation) {
  const auto spec = study::read_study(write_study("ensemble.toml", R"(
[base.particle]
shape = "cuboid"
size = [1.0e-3, 1.0e-3, 1.0e-3]
density = 1050.0
[base.domain]
size = [6.0e-3, 6.0e-3, 12.0e-3]
[orientations]
count = 4
seed = 3
)"));
  const auto cases = study::expand(spec);
  ASSERT_EQ(cases.size(), 4u);
  EXPECT_EQ(study::describe_inputs(cases[3].inputs), "orientation = 3");
  EXPECT_NE(cases[0].values.reals("particle.euler"), cases[1].values.reals("particle.euler"));
}

TEST(StudySpec, BadStudiesAreRefusedWholeNamingTheKey) {
  EXPECT_NE(refusal(kBase + "[vary]\nnumerics.cells_per_diamter = [8, 10]\n")
                .find("did you mean numerics.cells_per_diameter"),
            std::string::npos);
  EXPECT_NE(refusal(kBase + "[vary]\nnumerics.cells_per_diameter = [8, 2]\n")
                .find("case 1 (numerics.cells_per_diameter = 2)"),
            std::string::npos);
  EXPECT_NE(refusal(kBase + "[vary]\nreynolds = { from = 1, to = 5, step = 0 }\n").find("vary.reynolds.step"),
            std::string::npos);
  EXPECT_NE(refusal(kBase + "[vary]\ngalileo = [100]\n").find("galileo:"), std::string::npos);
  EXPECT_NE(refusal(kBase + "[vary]\nreynolds = 5\n").find("expected a list"), std::string::npos);
  EXPECT_NE(refusal(kBase + "[varry]\nreynolds = [5]\n").find("unknown key 'varry'"), std::string::npos);
  EXPECT_NE(refusal(kBase).find("nothing to vary"), std::string::npos);
  EXPECT_NE(refusal("[vary]\nreynolds = [5]\n").find("neither"), std::string::npos);
  EXPECT_NE(refusal(kBase + "[vary]\nreynolds = [5]\nparticle.towing_velocity = [[0, 0, -1]]\n").find("varied too"),
            std::string::npos);
  EXPECT_NE(refusal(kBase + "[vary]\ndomain_width_diameters = [6]\ndomain.size = [[0.01, 0.01, 0.02]]\n")
                .find("window inputs"),
            std::string::npos);
}

}  // namespace test_study_spec
