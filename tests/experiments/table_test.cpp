// An experiment's Table (experiments/table.h): the CSV writes each cell as its column says (a
// stream's significant digits, 0/1 flags, empty cells, JSON numbers, quotes), a summary-only
// column stays out of the CSV but not the summary's rows; the schema lists every column; a row
// of the wrong width, a cell of the wrong kind or a column declared twice is refused naming the
// table and the column; an unwritable file is an error naming it.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "experiments/columns.h"
#include "experiments/table.h"
#include "tests/test_util.h"

namespace physik::experiments {
namespace {

std::string temp_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("physik_table_test_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d.string();
}

Table sample() {
  Table t("sample", "sample.csv",
          {columns::kScene, columns::kDamping, columns::kStepsToConverge, columns::kConverged,
           real("x9", "m", "nine digits", 9),
           real("gap", "m", "blank if not finite").blank_if_nonfinite(),
           real("exact", "", "shortest exact").as_json_number(),
           text("label", "may hold commas").in_quotes(),
           flag("physical", "summary only").summary_only()});
  const double inf = std::numeric_limits<double>::infinity();
  t.add({"pinhead", 1.0 / 3.0, 42, true, M_PI, inf, 0.1, "a, b", false});
  t.add({"fig5", 1000000.0, -1, false, 2.0, 0.5, 1e-300, "c", true});
  return t;
}

TEST(Table, TheCsvWritesEachCellAsItsColumnSays) {
  const std::string dir = temp_dir("csv");
  sample().write_csv(dir);
  EXPECT_EQ(test::read_file(dir + "/sample.csv"),
            "scene,damping,steps_to_converge,converged,x9,gap,exact,label\n"
            "pinhead,0.333333,42,1,3.14159265,,0.1,\"a, b\"\n"
            "fig5,1e+06,-1,0,2,0.5,1e-300,\"c\"\n");
}

TEST(Table, TheSummaryRowsAreTypedAndHoldTheSummaryOnlyColumn) {
  const nlohmann::json rows = sample().rows_json();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["steps_to_converge"], 42);
  EXPECT_EQ(rows[0]["converged"], true);
  EXPECT_TRUE(rows[0]["gap"].is_null());  // not finite: null, never NaN in output
  EXPECT_EQ(rows[1]["physical"], true);
  EXPECT_DOUBLE_EQ(rows[0]["damping"].get<double>(), 1.0 / 3.0);  // full precision, not 6 digits
}

TEST(Table, TheSchemaListsEveryColumnWithItsFormat) {
  const nlohmann::json s = sample().schema();
  EXPECT_EQ(s["file"], "sample.csv");
  EXPECT_EQ(s["rows"], 2);
  ASSERT_EQ(s["columns"].size(), 9u);
  EXPECT_EQ(s["columns"][1]["format"], "g6");
  EXPECT_EQ(s["columns"][1]["unit"], "N s/m");
  EXPECT_EQ(s["columns"][4]["format"], "g9");
  EXPECT_EQ(s["columns"][5]["format"], "g6|blank");
  EXPECT_EQ(s["columns"][6]["format"], "json");
  EXPECT_EQ(s["columns"][7]["format"], "quoted");
  EXPECT_EQ(s["columns"][8]["csv"], false);
  EXPECT_FALSE(Table("only", "", {columns::kDt}).schema().contains("file"));
}

TEST(Table, BadRowsAndColumnsAreRefusedNamingTableAndColumn) {
  Table t("runs", "runs.csv", {columns::kScene, columns::kStepsToConverge});
  try {
    t.add({"pinhead"});
    FAIL() << "a short row was accepted";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("'runs'"), std::string::npos) << e.what();
  }
  try {
    t.add({"pinhead", 2.5});
    FAIL() << "a real in an integer column was accepted";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("steps_to_converge"), std::string::npos) << e.what();
  }
  EXPECT_EQ(t.size(), 0u);
  EXPECT_THROW(Table("dup", "dup.csv", {columns::kDt, columns::kDt}), std::logic_error);
}

TEST(Table, AnUnwritableFileIsAnErrorNamingIt) {
  Table t("runs", "runs.csv", {columns::kScene});
  try {
    t.write_csv("/nonexistent_physik_dir");
    FAIL() << "writing into a missing folder succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_physik_dir/runs.csv"), std::string::npos);
  }
}

}  // namespace
}  // namespace physik::experiments
