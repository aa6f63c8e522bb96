#pragma once
// A table of text cells and the two ways the reports print one (Markdown and HTML), so that a section is
// built once and written to both report.md and report.html.
#include <string>
#include <vector>

namespace aovar::report {

struct Grid {
  std::vector<std::string> header;
  std::vector<bool> numeric;  // per column: right-aligned in Markdown (default: left)
  std::vector<std::vector<std::string>> rows;
};

std::string html_escape(const std::string& s);
std::string markdown(const Grid& g);  // a Markdown table, then a blank line
std::string html(const Grid& g);      // <table>, every cell escaped

}  // namespace aovar::report
