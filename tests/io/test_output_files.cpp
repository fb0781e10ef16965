// The column table of timeseries.csv (io/output_files.hpp): the header and the sidecar
// timeseries.json come from it alike, a row carries the attitude's quaternion, a restart refuses a
// file of other columns, and docs/user-guide.md's table names every column.
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "attitude/attitude.hpp"
#include "common/error.hpp"
#include "io/output_files.hpp"

namespace test_output_files {

namespace fs = std::filesystem;
using settle::io::timeseries_column_table;
using settle::io::timeseries_columns;

std::string text_of(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  for (std::string field; std::getline(stream, field, ',');) fields.push_back(field);
  return fields;
}

class OutputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("settle_output_files_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST(TimeseriesColumns, SidecarListsTheHeaderColumnsInOrderWithUnits) {
  const auto sidecar = nlohmann::json::parse(settle::io::timeseries_sidecar_json());
  ASSERT_EQ(sidecar["columns"].size(), timeseries_columns().size());
  for (std::size_t i = 0; i < timeseries_columns().size(); ++i) {
    const auto& column = sidecar["columns"][i];
    EXPECT_EQ(column["name"], timeseries_columns()[i]);
    EXPECT_FALSE(column["unit"].get<std::string>().empty()) << column;
    const std::string frame = column["frame"];
    EXPECT_TRUE(frame.empty() || frame == "inertial" || frame == "body" || frame == "body to inertial") << column;
  }
  EXPECT_EQ(sidecar["file"], "timeseries.csv");
}

// The user guide's column table ("### timeseries.csv") names the columns in backticks, several to
// a cell ("`x, y, z`"): together they must be exactly the table's columns.
TEST(TimeseriesColumns, TheUserGuidesTableNamesEveryColumn) {
  const std::string guide = text_of(fs::path(SETTLE_SOURCE_DIR) / "docs" / "user-guide.md");
  const std::size_t start = guide.find("### timeseries.csv");
  ASSERT_NE(start, std::string::npos);
  const std::string section = guide.substr(start, guide.find("\n### ", start + 1) - start);
  std::set<std::string> documented;
  const std::regex first_cell(R"(\n\| `([^`]+)` \|)");
  for (auto it = std::sregex_iterator(section.begin(), section.end(), first_cell); it != std::sregex_iterator(); ++it) {
    std::stringstream names((*it)[1].str());
    for (std::string name; std::getline(names >> std::ws, name, ',');) documented.insert(name);
  }
  const std::set<std::string> written(timeseries_columns().begin(), timeseries_columns().end());
  EXPECT_EQ(documented, written);
}

TEST_F(OutputFiles, ARowCarriesTheAttitudesQuaternionAndTheSidecarIsWritten) {
  const fs::path csv = dir_ / "timeseries.csv";
  settle::coupling::Sample sample;
  sample.t_si = 0.25;
  // Set 2 active (theta = 1.2 > pi/4), so the quaternion is composed in the other order.
  sample.attitude = settle::attitude::Attitude::from_set1(0.3, 1.2, -0.7).in_set(settle::attitude::EulerSet::set2);
  {
    settle::io::TimeseriesWriter writer(csv);
    writer.write(sample);
  }
  EXPECT_EQ(text_of(dir_ / "timeseries.json"), settle::io::timeseries_sidecar_json());
  std::ifstream in(csv);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  const std::vector<std::string> names = split(header), values = split(row);
  ASSERT_EQ(names.size(), values.size());
  std::map<std::string, double> value;
  for (std::size_t i = 0; i < names.size(); ++i) value[names[i]] = std::stod(values[i]);
  // The quaternion of the same rotation from the set-1 angles by Eigen's angle-axis products:
  // another route through round-off only (the chart was converted through the matrix), so 1e-14.
  const Eigen::Quaterniond expected = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(1.2, Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitX());
  const double sign = expected.w() < 0.0 ? -1.0 : 1.0;
  EXPECT_NEAR(value["q_w"], sign * expected.w(), 1e-14);
  EXPECT_NEAR(value["q_x"], sign * expected.x(), 1e-14);
  EXPECT_NEAR(value["q_y"], sign * expected.y(), 1e-14);
  EXPECT_NEAR(value["q_z"], sign * expected.z(), 1e-14);
  EXPECT_EQ(value["euler_set"], 2.0);
}

// A restart of a run whose file has other columns (an older settle's) would append rows that do
// not match its header: refused, the file untouched.
TEST_F(OutputFiles, ContinuingAFileOfOtherColumnsIsRefused) {
  const fs::path csv = dir_ / "timeseries.csv";
  const std::string older = "t,x,y,z\n0,0,0,0\n";
  std::ofstream(csv) << older;
  EXPECT_THROW(settle::io::TimeseriesWriter::continue_at(csv, older.size()), settle::InputError);
  EXPECT_EQ(text_of(csv), older);
}

}  // namespace test_output_files
