#include "bake/png_encode.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <memory>

namespace exao::bake {
namespace {

void append(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + length);
}

void flush(png_structp) {}

}  // namespace

Result<void> check_png_bits(int bits) {
  if (bits != 8 && bits != 16) return fail("png_bits: must be 8 or 16, got " + std::to_string(bits));
  return {};
}

Result<std::vector<std::uint8_t>> encode_grey_png(std::span<const float> values, int width, int height, int bits) {
  if (auto ok = check_png_bits(bits); !ok) return std::unexpected(ok.error());
  if (width < 1 || height < 1 || values.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
    return fail("AO map: bad size " + std::to_string(width) + " x " + std::to_string(height));
  }
  const std::size_t bytes_per_texel = bits == 16 ? 2 : 1;
  const double top = bits == 16 ? 65535.0 : 255.0;
  std::vector<std::uint8_t> pixels(values.size() * bytes_per_texel);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float v = std::isnan(values[i]) ? 0.0f : std::clamp(values[i], 0.0f, 1.0f);
    const auto level = static_cast<std::uint32_t>(std::lround(static_cast<double>(v) * top));
    if (bits == 16) {  // PNG stores 16-bit samples big-endian
      pixels[2 * i] = static_cast<std::uint8_t>(level >> 8);
      pixels[2 * i + 1] = static_cast<std::uint8_t>(level & 0xff);
    } else {
      pixels[i] = static_cast<std::uint8_t>(level);
    }
  }
  // On the heap: libpng's longjmp must not find a local it changed since setjmp.
  auto out = std::make_unique<std::vector<std::uint8_t>>();
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    return fail("AO map: libpng could not start");
  }
  // libpng reports errors by longjmp; nothing with a destructor is created past this point.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return fail("AO map: libpng failed to encode");
  }
  png_set_write_fn(png, out.get(), &append, &flush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bits, PNG_COLOR_TYPE_GRAY,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const std::size_t row = static_cast<std::size_t>(width) * bytes_per_texel;
  for (int y = 0; y < height; ++y) png_write_row(png, pixels.data() + static_cast<std::size_t>(y) * row);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return std::move(*out);
}

}  // namespace exao::bake
