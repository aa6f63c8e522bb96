#include "report/grid.h"

namespace aovar::report {

std::string html_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '<') out += "&lt;";
    else if (ch == '>') out += "&gt;";
    else if (ch == '&') out += "&amp;";
    else if (ch == '"') out += "&quot;";
    else out += ch;
  }
  return out;
}

std::string markdown(const Grid& g) {
  std::string out = "|";
  for (const auto& h : g.header) out += " " + h + " |";
  out += "\n|";
  for (std::size_t c = 0; c < g.header.size(); ++c) out += c < g.numeric.size() && g.numeric[c] ? "---:|" : "---|";
  out += "\n";
  for (const auto& row : g.rows) {
    out += "|";
    for (const auto& cell : row) out += " " + cell + " |";
    out += "\n";
  }
  return out + "\n";
}

std::string html(const Grid& g) {
  std::string out = "<table><tr>";
  for (const auto& h : g.header) out += "<th>" + html_escape(h) + "</th>";
  out += "</tr>";
  for (const auto& row : g.rows) {
    out += "<tr>";
    for (const auto& cell : row) out += "<td>" + html_escape(cell) + "</td>";
    out += "</tr>";
  }
  return out + "</table>";
}

}  // namespace aovar::report
