#include "canvas.hpp"

#include <cairo-svg.h>

#include <algorithm>
#include <cctype>
#include <cstdarg>
#include <cstdio>

namespace ucon {
namespace plot {
namespace detail {

namespace {
// One font, installed with cairo's fontconfig on Debian (fonts-dejavu-core).
constexpr const char* kFont = "DejaVu Sans";
}  // namespace

Format formatOf(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos) return Format::kUnknown;
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == "png") return Format::kPng;
  if (ext == "svg") return Format::kSvg;
  return Format::kUnknown;
}

Canvas::~Canvas() {
  if (cr_) cairo_destroy(cr_);
  if (surface_) cairo_surface_destroy(surface_);
}

bool Canvas::open(const std::string& path, int width, int height, std::string* error) {
  format_ = formatOf(path);
  path_ = path;
  width_ = width;
  height_ = height;
  if (width < 200 || height < 150 || width > 20000 || height > 20000) {
    if (error) *error = fmt("picture size %dx%d out of range [200..20000]x[150..20000]", width, height);
    return false;
  }
  switch (format_) {
    case Format::kPng: surface_ = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height); break;
    case Format::kSvg: surface_ = cairo_svg_surface_create(path.c_str(), width, height); break;
    case Format::kUnknown:
      if (error) *error = path + ": unknown picture format (use .png or .svg)";
      return false;
  }
  if (cairo_surface_status(surface_) != CAIRO_STATUS_SUCCESS) {
    if (error) *error = path + ": " + cairo_status_to_string(cairo_surface_status(surface_));
    return false;
  }
  cr_ = cairo_create(surface_);
  cairo_set_source_rgb(cr_, 1, 1, 1);
  cairo_paint(cr_);
  return true;
}

bool Canvas::finish(std::string* error) {
  cairo_status_t st = cairo_status(cr_);
  if (st == CAIRO_STATUS_SUCCESS) {
    cairo_surface_flush(surface_);
    if (format_ == Format::kPng) {
      st = cairo_surface_write_to_png(surface_, path_.c_str());
    } else {
      cairo_surface_finish(surface_);
      st = cairo_surface_status(surface_);
    }
  }
  if (st != CAIRO_STATUS_SUCCESS) {
    if (error) *error = path_ + ": " + cairo_status_to_string(st);
    return false;
  }
  return true;
}

void setColour(cairo_t* cr, const Rgb& c, double alpha) { cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha); }

void text(cairo_t* cr, double x, double y, const std::string& s, double size, Align align, bool bold) {
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t ext;
  cairo_text_extents(cr, s.c_str(), &ext);
  double x0 = x;
  if (align == Align::kCentre) x0 = x - ext.x_advance / 2.0;
  if (align == Align::kRight) x0 = x - ext.x_advance;
  cairo_move_to(cr, x0, y);
  cairo_show_text(cr, s.c_str());
  cairo_new_path(cr);
}

double textWidth(cairo_t* cr, const std::string& s, double size, bool bold) {
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t ext;
  cairo_text_extents(cr, s.c_str(), &ext);
  return ext.x_advance;
}

std::string fmt(const char* f, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof(buf), f, ap);
  va_end(ap);
  return buf;
}

}  // namespace detail
}  // namespace plot
}  // namespace ucon
