#include "util/schema.h"

#include <fmt/format.h>

#include <stdexcept>

#include "util/fs.h"

namespace aovar::util {

void check_schema_version(const nlohmann::json& version, const std::filesystem::path& file) {
  const std::string where = display_path(file);
  if (!version.is_number_integer() || version.get<long long>() < 1)
    throw NewerSchema(fmt::format("{}: error: schema_version {} is not a version (a positive integer); write "
                                         "the file again with aovar",
                                         where, version.dump()));
  const long long v = version.get<long long>();
  if (v > kSchemaVersion)
    throw NewerSchema(fmt::format("{}: error: schema_version {} is newer than this aovar reads ({}): upgrade "
                                         "aovar, or write the file again with this one",
                                         where, v, kSchemaVersion));
}

}  // namespace aovar::util
