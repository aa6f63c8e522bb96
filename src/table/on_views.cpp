#include "table/on_views.h"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace aovar::table {

CostTable rows_on_views(const CostTable& table, const std::vector<std::string>& views) {
  CostTable out;
  out.meta = table.meta;
  for (const CostRow& r : table.rows)
    if (std::find(views.begin(), views.end(), r.view) != views.end()) out.rows.push_back(r);
  return out;
}

CostTable decided_rows(const CostTable& table, const std::string& target) {
  const nlohmann::json& ship = table.meta.ship;
  if (!ship.is_object() || !ship.contains("holdout_views")) return table;
  try {
    CostTable out = rows_on_views(table, ship.at("holdout_views").get<std::vector<std::string>>());
    for (const nlohmann::json& choice : ship.value("choices", nlohmann::json::array())) {
      if (choice.at("target").get<std::string>() != target || !choice.contains("survivors")) continue;
      const auto keys = choice.at("survivors").get<std::set<std::string>>();
      std::erase_if(out.rows, [&](const CostRow& r) { return !keys.count(r.variant); });
    }
    return out;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("cost table meta.ship: ") + e.what());
  }
}

}  // namespace aovar::table
