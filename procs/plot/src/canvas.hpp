#pragma once
// Private: a cairo surface chosen by the output file's extension (.png or .svg) and a few
// drawing helpers shared by the run picture and the benchmark chart. Cairo stays out of the
// public headers.

#include <cairo.h>

#include <memory>
#include <string>

#include "ucon/plot/geometry.hpp"

namespace ucon {
namespace plot {
namespace detail {

enum class Format { kPng, kSvg, kUnknown };
Format formatOf(const std::string& path);

/// Owns the cairo surface and context. PNG is drawn into memory and written by finish();
/// SVG is streamed to the file by cairo and completed by finish().
class Canvas {
 public:
  Canvas() = default;
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  /// false (and *error) for an unknown extension or a file that cannot be created.
  bool open(const std::string& path, int width, int height, std::string* error);
  /// Writes/completes the file; false (and *error) when cairo reports a failure.
  bool finish(std::string* error);
  cairo_t* cr() const { return cr_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
  Format format_ = Format::kUnknown;
  std::string path_;
  int width_ = 0, height_ = 0;
};

enum class Align { kLeft, kCentre, kRight };

void setColour(cairo_t* cr, const Rgb& c, double alpha = 1.0);
/// Text with its baseline at y; size in px.
void text(cairo_t* cr, double x, double y, const std::string& s, double size, Align align = Align::kLeft,
          bool bold = false);
double textWidth(cairo_t* cr, const std::string& s, double size, bool bold = false);
/// printf-style formatting into std::string.
std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));

}  // namespace detail
}  // namespace plot
}  // namespace ucon
