#include "ssao/contact_sheet.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "ssao/label_font.h"

namespace exao::ssao {
namespace {

constexpr std::uint8_t kNone[3] = {40, 44, 52};

std::uint8_t to_byte(double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

RgbImage shrink(const RgbImage& in, int factor) {
  RgbImage out;
  out.width = in.width / factor;
  out.height = in.height / factor;
  out.rgb.assign(3 * static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height), 0);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      for (int k = 0; k < 3; ++k) {
        int sum = 0;
        for (int sy = 0; sy < factor; ++sy) {
          for (int sx = 0; sx < factor; ++sx) {
            sum += in.rgb[3 * (static_cast<std::size_t>(y * factor + sy) * static_cast<std::size_t>(in.width) + static_cast<std::size_t>(x * factor + sx)) + static_cast<std::size_t>(k)];
          }
        }
        out.rgb[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(out.width) + static_cast<std::size_t>(x)) + static_cast<std::size_t>(k)] =
            static_cast<std::uint8_t>(sum / (factor * factor));
      }
    }
  }
  return out;
}

void blit(RgbImage& dst, const RgbImage& src, int x0, int y0) {
  for (int y = 0; y < src.height; ++y) {
    std::copy_n(src.rgb.begin() + 3 * static_cast<std::ptrdiff_t>(y) * src.width, 3 * src.width,
                dst.rgb.begin() + 3 * (static_cast<std::ptrdiff_t>(y0 + y) * dst.width + x0));
  }
}

}  // namespace

RgbImage grey_image(std::span<const float> ao, std::span<const std::uint8_t> valid, int width, int height) {
  RgbImage img{width, height, std::vector<std::uint8_t>(3 * ao.size())};
  for (std::size_t p = 0; p < ao.size(); ++p) {
    for (std::size_t k = 0; k < 3; ++k) img.rgb[3 * p + k] = valid[p] ? to_byte(ao[p]) : kNone[k];
  }
  return img;
}

RgbImage heat_map(std::span<const float> ao, std::span<const float> exact, std::span<const std::uint8_t> valid,
                  int width, int height, double full_scale) {
  RgbImage img{width, height, std::vector<std::uint8_t>(3 * ao.size())};
  for (std::size_t p = 0; p < ao.size(); ++p) {
    if (!valid[p]) {
      for (std::size_t k = 0; k < 3; ++k) img.rgb[3 * p + k] = kNone[k];
      continue;
    }
    const double d = static_cast<double>(ao[p]) - static_cast<double>(exact[p]);
    const double t = std::min(std::abs(d) / full_scale, 1.0);
    // Lighter than exact: toward (40, 90, 255); darker: toward (230, 30, 30).
    const double target[3] = {d > 0 ? 40.0 : 230.0, d > 0 ? 90.0 : 30.0, d > 0 ? 255.0 : 30.0};
    for (std::size_t k = 0; k < 3; ++k) img.rgb[3 * p + k] = to_byte(((1.0 - t) * 255.0 + t * target[k]) / 255.0);
  }
  return img;
}

RgbImage heat_map_legend(int width, int height, double full_scale) {
  const int bar_top = height / 3, bar_bottom = 2 * height / 3;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::vector<float> ao(n, 0.0f), exact(n, 0.0f);
  std::vector<std::uint8_t> valid(n, 1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
      const bool bar = y >= bar_top && y < bar_bottom;
      ao[p] = bar ? static_cast<float>(full_scale * (2.0 * (x + 0.5) / width - 1.0)) : 0.0f;
    }
  }
  RgbImage img = heat_map(ao, exact, valid, width, height, full_scale);
  const std::uint8_t ink[3] = {20, 20, 20};
  const int scale = std::max(1, width / 160);
  const auto label = [&](const std::string& text, int x, int y) { draw_text(img.rgb, width, height, x, y, text, scale, ink); };
  label("ERROR AO - EXACT", (width - text_width("ERROR AO - EXACT", scale)) / 2, bar_top - (kGlyphHeight + 3) * scale);
  label("DARKER", 2, bar_bottom + 3 * scale);
  label("LIGHTER", width - text_width("LIGHTER", scale) - 2, bar_bottom + 3 * scale);
  char range[32];
  std::snprintf(range, sizeof range, "-%.2f", full_scale);
  label(range, 2, bar_top - (kGlyphHeight + 3) * scale * 2);
  std::snprintf(range, sizeof range, "+%.2f", full_scale);
  label(range, width - text_width(range, scale) - 2, bar_top - (kGlyphHeight + 3) * scale * 2);
  return img;
}

RgbImage contact_sheet(std::span<const SheetCell> cells, int columns, int tile_width) {
  RgbImage sheet;
  if (cells.empty() || !cells.front().top) return sheet;
  const int factor = std::max(1, (cells.front().top->width + tile_width - 1) / tile_width);
  const int tw = cells.front().top->width / factor, th = cells.front().top->height / factor;
  const int scale = std::clamp(tw / 120, 1, 2), label_height = kGlyphHeight * scale + 8, gap = 6;
  const std::size_t fits = static_cast<std::size_t>((tw + scale) / ((kGlyphWidth + 1) * scale));
  bool any_bottom = false;
  for (const SheetCell& c : cells) any_bottom = any_bottom || c.bottom;
  const int cell_w = tw + gap, cell_h = label_height + th + (any_bottom ? th + 2 : 0) + gap;
  const int rows = (static_cast<int>(cells.size()) + columns - 1) / columns;
  const int used_columns = std::min(columns, static_cast<int>(cells.size()));
  sheet.width = used_columns * cell_w + gap;
  sheet.height = rows * cell_h + gap;
  sheet.rgb.assign(3 * static_cast<std::size_t>(sheet.width) * static_cast<std::size_t>(sheet.height), 255);
  const std::uint8_t ink[3] = {20, 20, 20};
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const int x0 = gap + static_cast<int>(i % static_cast<std::size_t>(columns)) * cell_w;
    const int y0 = gap + static_cast<int>(i / static_cast<std::size_t>(columns)) * cell_h;
    draw_text(sheet.rgb, sheet.width, sheet.height, x0, y0 + 2, std::string_view(cells[i].label).substr(0, fits), scale, ink);
    blit(sheet, shrink(*cells[i].top, factor), x0, y0 + label_height);
    if (cells[i].bottom) blit(sheet, shrink(*cells[i].bottom, factor), x0, y0 + label_height + th + 2);
  }
  return sheet;
}

}  // namespace exao::ssao
