// Table (table.h): the CSV, the summary's rows, the schema and the report table, each from the
// columns declared once.
#include "experiments/table.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "physik/io/json_fields.h"
#include "physik/io/pose_io.h"

namespace physik::experiments {

namespace {

const char* kind_name(CellKind k) {
  switch (k) {
    case CellKind::kReal:
      return "a real";
    case CellKind::kInt:
      return "an integer";
    case CellKind::kFlag:
      return "a flag";
    case CellKind::kText:
      return "a text";
  }
  return "?";
}

[[noreturn]] void wrong_kind(const Column& c, const std::string& table) {
  throw std::logic_error("table '" + table + "': column '" + c.name + "' takes " +
                         kind_name(c.kind) + ", given another kind of cell");
}

std::string real_text(double v, const Column& c) {
  if (c.blank_nonfinite && !std::isfinite(v)) return "";
  if (c.json_number) return nlohmann::json(v).dump();
  std::ostringstream s;
  s << std::setprecision(c.digits) << v;
  return s.str();
}

}  // namespace

Column Column::named(std::string other) const {
  Column c = *this;
  c.name = std::move(other);
  return c;
}

Column Column::with_digits(int d) const {
  Column c = *this;
  c.digits = d;
  return c;
}

Column Column::blank_if_nonfinite() const {
  Column c = *this;
  c.blank_nonfinite = true;
  return c;
}

Column Column::as_json_number() const {
  Column c = *this;
  c.json_number = true;
  return c;
}

Column Column::in_quotes() const {
  Column c = *this;
  c.quoted = true;
  return c;
}

Column Column::summary_only() const {
  Column c = *this;
  c.in_csv = false;
  return c;
}

std::string Column::format() const {
  switch (kind) {
    case CellKind::kReal:
      return (json_number ? std::string("json") : "g" + std::to_string(digits)) +
             (blank_nonfinite ? "|blank" : "");
    case CellKind::kInt:
      return "int";
    case CellKind::kFlag:
      return "flag";
    case CellKind::kText:
      return quoted ? "quoted" : "text";
  }
  return "";
}

Column real(std::string name, std::string unit, std::string doc, int digits) {
  Column c{std::move(name), std::move(unit), std::move(doc)};
  c.digits = digits;
  return c;
}

Column integer(std::string name, std::string unit, std::string doc) {
  Column c{std::move(name), std::move(unit), std::move(doc)};
  c.kind = CellKind::kInt;
  return c;
}

Column flag(std::string name, std::string doc) {
  Column c{std::move(name), "", std::move(doc)};
  c.kind = CellKind::kFlag;
  return c;
}

Column text(std::string name, std::string doc) {
  Column c{std::move(name), "", std::move(doc)};
  c.kind = CellKind::kText;
  return c;
}

void Cell::write_csv(std::ostream& out, const Column& c, const std::string& table) const {
  if (empty()) return;
  switch (c.kind) {
    case CellKind::kReal:
      // an integer in a real column is written as the integer it is (`out << int`)
      if (const auto* i = std::get_if<long long>(&v_)) {
        out << *i;
      } else if (const auto* d = std::get_if<double>(&v_)) {
        out << real_text(*d, c);
      } else {
        wrong_kind(c, table);
      }
      return;
    case CellKind::kInt:
      if (const auto* i = std::get_if<long long>(&v_))
        out << *i;
      else
        wrong_kind(c, table);
      return;
    case CellKind::kFlag:
      if (const auto* b = std::get_if<bool>(&v_))
        out << (*b ? 1 : 0);
      else
        wrong_kind(c, table);
      return;
    case CellKind::kText:
      if (const auto* s = std::get_if<std::string>(&v_)) {
        out << (c.quoted ? "\"" + *s + "\"" : *s);
      } else {
        wrong_kind(c, table);
      }
      return;
  }
}

nlohmann::json Cell::to_json(const Column& c, const std::string& table) const {
  if (empty()) return nullptr;
  std::ostringstream check;  // the same kind check as the CSV's
  write_csv(check, c, table);
  return std::visit(
      [](const auto& v) -> nlohmann::json {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return nullptr;
        } else if constexpr (std::is_same_v<T, double>) {
          return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
        } else {
          return v;
        }
      },
      v_);
}

Cell::Cell(const Cell&) = default;
Cell::Cell(Cell&&) noexcept = default;
Cell& Cell::operator=(const Cell&) = default;
Cell& Cell::operator=(Cell&&) noexcept = default;
Cell::~Cell() = default;

std::string Cell::display(const Column& c, int digits, const std::string& table) const {
  if (empty()) return "";
  if (const auto* b = std::get_if<bool>(&v_)) return *b ? "yes" : "no";
  if (const auto* d = std::get_if<double>(&v_)) {
    std::ostringstream s;
    s << std::setprecision(digits) << *d;
    return s.str();
  }
  std::ostringstream s;
  write_csv(s, c, table);
  return s.str();
}

Table::Table(std::string name, std::string file, std::vector<Column> columns)
    : name_(std::move(name)), file_(std::move(file)), columns_(std::move(columns)) {
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (columns_[i].name == columns_[j].name) {
        throw std::logic_error("table '" + name_ + "': column '" + columns_[i].name +
                               "' declared twice");
      }
    }
  }
}

void Table::add(std::vector<Cell> row) {
  if (row.size() != columns_.size()) {
    throw std::logic_error("table '" + name_ + "': a row of " + std::to_string(row.size()) +
                           " cells for " + std::to_string(columns_.size()) + " columns");
  }
  std::ostringstream check;  // a cell of the wrong kind fails here, where it was added
  for (std::size_t k = 0; k < row.size(); ++k) row[k].write_csv(check, columns_[k], name_);
  rows_.push_back(std::move(row));
}

std::size_t Table::index_of(const std::string& column) const {
  for (std::size_t k = 0; k < columns_.size(); ++k) {
    if (columns_[k].name == column) return k;
  }
  throw std::logic_error("table '" + name_ + "': no column '" + column + "'");
}

nlohmann::json Table::value(std::size_t row, const std::string& column) const {
  const std::size_t k = index_of(column);
  return rows_.at(row)[k].to_json(columns_[k], name_);
}

void Table::write_csv(const std::string& dir) const {
  const std::string path = dir + "/" + file_;
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write file");
  const auto line = [&](const auto& cell) {
    bool first = true;
    for (std::size_t k = 0; k < columns_.size(); ++k) {
      if (!columns_[k].in_csv) continue;
      if (!first) out << ",";
      first = false;
      cell(k);
    }
    out << "\n";
  };
  line([&](std::size_t k) { out << columns_[k].name; });
  for (const auto& row : rows_) {
    line([&](std::size_t k) { row[k].write_csv(out, columns_[k], name_); });
  }
  if (!out) throw std::runtime_error(path + ": write failed");
}

nlohmann::json Table::rows_json() const {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : rows_) {
    nlohmann::json obj = nlohmann::json::object();
    for (std::size_t k = 0; k < row.size(); ++k) {
      obj[columns_[k].name] = row[k].to_json(columns_[k], name_);
    }
    rows.push_back(std::move(obj));
  }
  return rows;
}

nlohmann::json Table::schema() const {
  nlohmann::json cols = nlohmann::json::array();
  for (const Column& c : columns_) {
    cols.push_back({{"name", c.name},
                    {"unit", c.unit},
                    {"doc", c.doc},
                    {"format", c.format()},
                    {"csv", c.in_csv}});
  }
  nlohmann::json j = {{"columns", cols}, {"rows", rows_.size()}};
  if (!file_.empty()) j["file"] = file_;
  return j;
}

void Table::add_to_report(Report& report, const std::string& title,
                          const std::vector<ReportColumn>& columns, int digits,
                          const std::map<std::string, std::string>& labels) const {
  std::vector<std::string> headings;
  std::vector<std::size_t> index;
  for (const ReportColumn& c : columns) {
    headings.push_back(c.heading);
    index.push_back(index_of(c.column));
  }
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : rows_) {
    nlohmann::json cells = nlohmann::json::array();
    for (std::size_t k : index) {
      const std::string shown = row[k].display(columns_[k], digits, name_);
      const auto label = labels.find(shown);
      cells.push_back(columns_[k].kind == CellKind::kText && label != labels.end() ? label->second
                                                                                   : shown);
    }
    rows.push_back(std::move(cells));
  }
  report.table(title, headings, rows);
}

void write_bones_table(const std::string& path, const Rig& rig, const BoneFrames& frames) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write file");
  write_bones_csv(rig, frames, out);
  if (!out) throw std::runtime_error(path + ": write failed");
}

nlohmann::json table_schemas(const std::vector<const Table*>& tables) {
  nlohmann::json j = nlohmann::json::object();
  for (const Table* t : tables) {
    if (j.contains(t->name())) {
      throw std::logic_error("two tables named '" + t->name() + "' in one summary");
    }
    j[t->name()] = t->schema();
  }
  return j;
}

void write_summary(const Context& ctx, nlohmann::json doc, const Report& report,
                   const std::vector<const Table*>& tables) {
  doc["tables"] = table_schemas(tables);
  write_summary(ctx, std::move(doc), report);
}

}  // namespace physik::experiments
