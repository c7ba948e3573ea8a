// An experiment's table, its columns declared once. A Column says its name, its unit, what it
// means and how a CSV cell is written; a Table holds the rows an experiment measured and writes
// from them:
//   - the CSV (<out>/<file>), each cell as the column says (a C++ stream's format: significant
//     digits, booleans as 0/1, or the number as JSON writes it);
//   - the summary's rows: one JSON object per row, keyed by column name, the values typed (a
//     flag is true/false, a missing cell null, a non-finite number null);
//   - its schema, which summary.json records under "tables" (file; per column name, unit, doc,
//     format) so that analysis/ and python/ take column names from what the experiment wrote
//     (analysis/physik_plot.py read_table checks a CSV against it);
//   - a report table (report.h), a projection of some columns as the report shows them.
// The columns several experiments share (the same quantity under the same name) are in
// experiments/columns.h.
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/report.h"
#include "physik/model/kinematics.h"

namespace physik::experiments {

enum class CellKind { kReal, kInt, kFlag, kText };

struct Column {
  std::string name;
  std::string unit;  // "" for counts, flags and labels
  std::string doc;
  CellKind kind = CellKind::kReal;
  int digits = 6;                // reals: significant digits (6: a C++ stream's default)
  bool json_number = false;      // reals: written as JSON writes the number (shortest exact)
  bool blank_nonfinite = false;  // reals: an empty cell for inf and nan
  bool quoted = false;           // text: within double quotes (a cell that may hold commas)
  bool in_csv = true;            // false: the summary's rows hold it, the CSV does not

  // the same column under another name (a family of columns: one per run, per point)
  Column named(std::string other) const;
  Column with_digits(int d) const;
  Column blank_if_nonfinite() const;
  Column as_json_number() const;
  Column in_quotes() const;
  Column summary_only() const;
  // the column's format as the schema states it: "g<digits>" (a stream's %g), "json" (JSON's
  // shortest exact number), either with "|blank" (empty when not finite); "int"; "flag" (0/1);
  // "text"; "quoted" (text within double quotes)
  std::string format() const;
};

// A real number, written with `digits` significant digits (as num() in common.h).
Column real(std::string name, std::string unit, std::string doc, int digits = 6);
Column integer(std::string name, std::string unit, std::string doc);
// A yes/no measure: 0/1 in the CSV, true/false in the summary's rows.
Column flag(std::string name, std::string doc);
Column text(std::string name, std::string doc);

// One cell: a real, an integer, a flag, a text, or nothing (an empty CSV cell, JSON null).
class Cell {
 public:
  Cell() = default;
  Cell(double v) : v_(v) {}                    // NOLINT: implicit, so rows read as {a, b, c}
  Cell(bool v) : v_(v) {}                      // NOLINT
  Cell(const char* v) : v_(std::string(v)) {}  // NOLINT
  Cell(std::string v) : v_(std::move(v)) {}    // NOLINT
  template <class T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, int> = 0>
  Cell(T v) : v_(static_cast<long long>(v)) {}  // NOLINT
  // defined in table.cpp: inlined, moving the variant trips GCC 12's -Wmaybe-uninitialized on
  // its string alternative (a false positive) wherever a row is built with push_back
  Cell(const Cell&);
  Cell(Cell&&) noexcept;
  Cell& operator=(const Cell&);
  Cell& operator=(Cell&&) noexcept;
  ~Cell();

  bool empty() const { return std::holds_alternative<std::monostate>(v_); }
  // the value, checked against the column's kind (std::logic_error naming table and column)
  void write_csv(std::ostream& out, const Column& c, const std::string& table) const;
  nlohmann::json to_json(const Column& c, const std::string& table) const;
  // as a report cell shows it: reals with `digits` significant digits, flags yes/no
  std::string display(const Column& c, int digits, const std::string& table) const;

 private:
  std::variant<std::monostate, double, long long, bool, std::string> v_;
};

// One column of a report table: its heading and the table's column it shows.
struct ReportColumn {
  std::string heading;
  std::string column;
};

class Table {
 public:
  // `name` is the key of the table in summary.json's "tables"; `file` the CSV under the
  // experiment's folder ("" for a table only the summary holds)
  Table(std::string name, std::string file, std::vector<Column> columns);

  // One row: a cell per column, in the columns' order (std::logic_error otherwise).
  void add(std::vector<Cell> row);

  const std::string& name() const { return name_; }
  const std::string& file() const { return file_; }
  const std::vector<Column>& columns() const { return columns_; }
  std::size_t size() const { return rows_.size(); }
  // a row's cell, as the summary's rows hold it
  nlohmann::json value(std::size_t row, const std::string& column) const;

  // <dir>/<file>: the header, then every row (std::runtime_error naming the file if it cannot
  // be written)
  void write_csv(const std::string& dir) const;
  // every row as {column: value}
  nlohmann::json rows_json() const;
  // {"file": ..., "rows": n, "columns": [{"name", "unit", "doc", "format", "csv"}]} ("csv": false
  // for a column only the summary's rows hold)
  nlohmann::json schema() const;
  // A report table of some columns, cells as the report shows them (reals with `digits`
  // significant digits); a text cell found in `labels` is shown as its label.
  void add_to_report(Report& report, const std::string& title,
                     const std::vector<ReportColumn>& columns, int digits = 3,
                     const std::map<std::string, std::string>& labels = {}) const;

 private:
  std::size_t index_of(const std::string& column) const;

  std::string name_, file_;
  std::vector<Column> columns_;
  std::vector<std::vector<Cell>> rows_;
};

// A bones table (physik/io/pose_io.h's format: one row per bone, head and tail) to `path`
// (std::runtime_error naming the file if it cannot be written). Its columns are the format's,
// shared with the CLI and read back by read_bones, so it is not a Table.
void write_bones_table(const std::string& path, const Rig& rig, const BoneFrames& frames);

// The "tables" section of summary.json: each table's schema under its name.
nlohmann::json table_schemas(const std::vector<const Table*>& tables);

// Write <ctx.out_dir>/summary.json: `doc`, the report as its "report" section and the tables'
// schemas as its "tables" section.
void write_summary(const Context& ctx, nlohmann::json doc, const Report& report,
                   const std::vector<const Table*>& tables);

}  // namespace physik::experiments
