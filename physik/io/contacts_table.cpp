// The contacts table (contacts_table.h): the force stage's contacts, one row per contact per
// trajectory row.
#include "physik/io/contacts_table.h"

#include <cmath>
#include <iomanip>

namespace physik {

ContactsCsv::ContactsCsv(std::ostream& out) : out_(out) {
  const char* sep = "";
  for (const char* name : kContactsColumns) {
    out_ << sep << name;
    sep = ",";
  }
  out_ << "\n" << std::setprecision(9);
}

int ContactsCsv::write_rows(const SimState& s) {
  int rows = 0;
  for (const Contact& c : s.contact.found) {
    if (!c.point_world.allFinite() || !c.normal_world.allFinite() || !std::isfinite(c.depth) ||
        !std::isfinite(c.normal_force)) {
      continue;
    }
    const Vec3 &p = c.point_world, &n = c.normal_world;
    out_ << s.step << "," << s.time << "," << c.bone << "," << c.other_bone << "," << p.x() << ","
         << p.y() << "," << p.z() << "," << n.x() << "," << n.y() << "," << n.z() << "," << c.depth
         << "," << c.normal_force << "\n";
    ++rows;
  }
  return rows;
}

}  // namespace physik
