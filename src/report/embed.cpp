#include "report/embed.h"

#include <iostream>
#include <optional>

#include <fmt/format.h>

#include "report/grid.h"
#include "util/fs.h"
#include "util/path_names.h"

namespace aovar::report {
namespace fs = std::filesystem;

std::string base64(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 | (unsigned char)bytes[i + 2];
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    unsigned v = (unsigned char)bytes[i] << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

std::string image_tag(const fs::path& root, const fs::path& file, const std::string& caption, int width) {
  const auto without = [&](const char* why) {
    return "<figure><figcaption>" + html_escape(caption) + " (" + why + ")</figcaption></figure>";
  };
  if (file.empty()) return without("no image");
  if (!util::is_inside(root, file)) {
    std::cerr << "aovar report: warning: " << util::display_path(file) << " lies outside the table's folder "
              << util::display_path(root) << ": not embedded\n";
    return without("outside the table folder: not embedded");
  }
  std::optional<std::string> bytes;
  try {
    bytes = util::read_file(file);
  } catch (const util::ReadError& e) {  // a FIFO or a folder where an image should be: a caption, not a failure
    std::cerr << "aovar report: warning: " << e.what() << ": not embedded\n";
    return without("not a readable image: not embedded");
  }
  if (!bytes) return without("missing");
  const std::string size = width > 0 ? fmt::format(" width=\"{}\"", width) : "";
  return fmt::format("<figure><img src=\"data:image/png;base64,{}\"{}><figcaption>{}</figcaption></figure>", base64(*bytes),
                     size, html_escape(caption));
}

RowImages row_images(const table::CostRow& row, const fs::path& dir) {
  if (row.images.size() < 3) return {};
  RowImages out;
  out.preview = dir / row.images[1];
  out.error_map = dir / row.images[2];
  // images/<backend>/<view>/<key>.png under measure/<scene>/: the reference is images/reference/<view>.png.
  const fs::path scene_dir = out.preview.parent_path().parent_path().parent_path().parent_path();
  out.reference = scene_dir / "images" / "reference" / (row.view + ".png");
  return out;
}

}  // namespace aovar::report
