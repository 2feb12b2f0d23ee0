#include <string>

#include "ucon/viewer/viewer_data.hpp"

namespace ucon {
namespace viewer {
namespace detail {
extern const char kViewerPage[];  // page/viewer.html, embedded at build time
}  // namespace detail

namespace {
void replaceOnce(std::string* s, const std::string& what, const std::string& with) {
  const auto pos = s->find(what);
  if (pos != std::string::npos) s->replace(pos, what.size(), with);
}

std::string htmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}
}  // namespace

std::string renderViewerHtml(const std::string& json, const std::string& title) {
  // '<' can only occur inside JSON strings, where \u003c means the same: with none left, no
  // "</script>" or "<!--" in the data can end or confuse the script element.
  std::string data;
  data.reserve(json.size());
  for (char c : json) {
    if (c == '<') data += "\\u003c";
    else data += c;
  }
  std::string page = detail::kViewerPage;
  replaceOnce(&page, "__UCON_TITLE__", htmlEscape(title.empty() ? "UCON run" : title));
  replaceOnce(&page, "/*__UCON_DATA__*/", data);
  return page;
}

}  // namespace viewer
}  // namespace ucon
