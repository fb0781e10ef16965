// The timeseries.csv reader (analysis/timeseries.hpp): columns by header name, the typed
// settling series built from them, and the refusal of broken files with messages that name
// the file, the line or row, and the column.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "analysis/timeseries.hpp"
#include "attitude/attitude.hpp"
#include "common/error.hpp"

namespace test_timeseries {

using settle::InputError;
using namespace settle::analysis;

std::string message_of_parse(const std::string& text) {
  try {
    (void)parse_timeseries_csv(text, "run/timeseries.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string message_of_series(const std::string& text) {
  try {
    (void)settling_series(parse_timeseries_csv(text, "run/timeseries.csv"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A two-row timeseries.csv with every column of the settling series plus Re (as settle run
// writes it), the second row with the given set-1 angles.
std::string settling_csv(double psi, double theta, double gamma) {
  std::string text =
      "t,x,y,z,ux,uy,uz,wx,wy,wz,wbx,wby,wbz,psi,theta,gamma,psi_r,theta_r,gamma_r,euler_set,"
      "Fx,Fy,Fz,Tx,Ty,Tz,Re\n";
  text += "0,1,2,3,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,1,0,0,0,0,0,0,0\n";
  text += "0.5,1.1,2.2,3.3,0.01,0.02,-0.03,0.1,0.2,0.3,0.4,0.5,0.6," + std::to_string(psi) + "," +
          std::to_string(theta) + "," + std::to_string(gamma) + ",0,0,0,1,1e-6,2e-6,3e-6,4e-9,5e-9,6e-9,7.5\n";
  return text;
}

TEST(TimeseriesCsv, ReadsColumnsByName) {
  const Timeseries table = parse_timeseries_csv("t, a ,b\r\n0,1.5,-2\n\n0.25,+3,1e-3\n", "small.csv");
  ASSERT_EQ(table.rows(), 2u);
  ASSERT_EQ(table.names().size(), 3u);
  EXPECT_EQ(table.names()[1], "a");  // blanks around a name are not part of it
  // Decimal literals parse to the nearest double: exact comparison is the contract of from_chars.
  EXPECT_EQ(table.column("t")[1], 0.25);
  EXPECT_EQ(table.column("a")[0], 1.5);
  EXPECT_EQ(table.column("a")[1], 3.0);
  EXPECT_EQ(table.column("b")[1], 1e-3);
  EXPECT_TRUE(table.has("b"));
  EXPECT_FALSE(table.has("c"));
}

TEST(TimeseriesCsv, ReadsAFileFromDisk) {
  const auto path =
      std::filesystem::temp_directory_path() / ("settle_timeseries_" + std::to_string(::getpid()) + ".csv");
  {
    std::ofstream out(path);
    out << "t,uz\n0,0\n0.1,-0.02\n0.2,-0.03\n";
  }
  const Timeseries table = read_timeseries_csv(path);
  std::filesystem::remove(path);
  ASSERT_EQ(table.rows(), 3u);
  EXPECT_EQ(table.column("uz")[2], -0.03);
  EXPECT_EQ(table.source(), path.string());
}

TEST(TimeseriesCsv, MissingFileNamesIt) {
  try {
    (void)read_timeseries_csv("/nonexistent/dir/timeseries.csv");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/timeseries.csv"), std::string::npos) << e.what();
  }
}

TEST(TimeseriesCsv, BrokenFilesNameLineAndColumn) {
  EXPECT_NE(message_of_parse("").find("empty"), std::string::npos);
  EXPECT_NE(message_of_parse("t,,u\n").find("no name"), std::string::npos);
  EXPECT_NE(message_of_parse("t,u,t\n").find("'t' appears twice"), std::string::npos);
  const std::string short_row = message_of_parse("t,u\n0,1\n1\n");
  EXPECT_NE(short_row.find("run/timeseries.csv:3"), std::string::npos) << short_row;
  EXPECT_NE(short_row.find("expected 2 values"), std::string::npos) << short_row;
  const std::string bad_number = message_of_parse("t,u\n0,1\n1,x2\n");
  EXPECT_NE(bad_number.find("run/timeseries.csv:3: column 'u': not a number: 'x2'"), std::string::npos) << bad_number;
  EXPECT_NE(message_of_parse("t,u\n0,\n").find("column 'u': not a number"), std::string::npos);
}

TEST(TimeseriesCsv, MissingColumnIsNamed) {
  const Timeseries table = parse_timeseries_csv("t,ux\n0,1\n", "run/timeseries.csv");
  try {
    (void)table.column("uy");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "run/timeseries.csv: missing column 'uy'");
  }
}

TEST(SettlingSeries, BuiltFromTheColumnsOfSettleRun) {
  const double psi = 0.3, theta = -0.7, gamma = 2.1;
  const SettlingSeries s = settling_series(parse_timeseries_csv(settling_csv(psi, theta, gamma), "run.csv"));
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s.t_si[1], 0.5);
  EXPECT_EQ(s.position_si[1], Eigen::Vector3d(1.1, 2.2, 3.3));
  EXPECT_EQ(s.velocity_si[1], Eigen::Vector3d(0.01, 0.02, -0.03));
  EXPECT_EQ(s.angular_velocity_n_si[1], Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(s.angular_velocity_b_si[1], Eigen::Vector3d(0.4, 0.5, 0.6));
  EXPECT_EQ(s.force_si[1], Eigen::Vector3d(1e-6, 2e-6, 3e-6));
  EXPECT_EQ(s.torque_si[1], Eigen::Vector3d(4e-9, 5e-9, 6e-9));
  // The attitude is the set-1 matrix of the angles as printed (std::to_string keeps 6 decimals,
  // so the reference is built from the same rounded text): equal to round-off.
  const Eigen::Matrix3d expected =
      settle::attitude::Attitude::from_set1(std::stod(std::to_string(psi)), std::stod(std::to_string(theta)),
                                            std::stod(std::to_string(gamma)))
          .body_to_inertial();
  EXPECT_LT((s.body_to_inertial[1] - expected).norm(), 1e-15);
  EXPECT_LT((s.body_to_inertial[0] - Eigen::Matrix3d::Identity()).norm(), 1e-15);
}

TEST(SettlingSeries, RefusesMissingColumnsNonFiniteValuesAndTimeGoingBack) {
  std::string text = settling_csv(0, 0, 0);
  std::string without_uz = text;
  without_uz.replace(without_uz.find(",uz,"), 4, ",vz,");
  EXPECT_EQ(message_of_series(without_uz), "run/timeseries.csv: missing column 'uz'");

  std::string with_nan = text;
  with_nan.replace(with_nan.find("0.01"), 4, "nan");
  const std::string nan_message = message_of_series(with_nan);
  EXPECT_NE(nan_message.find("row 2: column 'ux' is not finite"), std::string::npos) << nan_message;

  std::string backwards = text;
  backwards.replace(backwards.find("\n0.5,") + 1, 3, "0.0");
  const std::string back_message = message_of_series(backwards);
  EXPECT_NE(back_message.find("row 2: column 't' must increase"), std::string::npos) << back_message;

  const std::string one_row = text.substr(0, text.find("\n0.5,") + 1);
  EXPECT_NE(message_of_series(one_row).find("1 data rows"), std::string::npos);
}

TEST(SettlingSeries, SinceTheReleaseKeepsTheSampleTakenAtIt) {
  // Sample times summed from steps (0.1 + 0.1 + 0.1 = 0.30000000000000004) land a rounding error
  // off the release time: that sample is the state at the release and belongs to the free motion.
  SettlingSeries series;
  double t = 0.0;
  for (int k = 0; k < 6; ++k, t += 0.1)
    series.add(t, Eigen::Vector3d(0.0, 0.0, -t), Eigen::Vector3d(0.0, 0.0, -1.0), Eigen::Vector3d::Zero(),
               Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
  const SettlingSeries free = series.since(0.3);
  ASSERT_EQ(free.size(), 3u);
  EXPECT_DOUBLE_EQ(free.t_si.front(), 0.3);
  EXPECT_EQ(free.position_si.front(), series.position_si[3]);
  EXPECT_EQ(series.since(0.0).size(), series.size());
  EXPECT_EQ(series.since(0.31).size(), 2u);
}

}  // namespace test_timeseries
