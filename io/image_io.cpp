#include "io/image_io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <memory>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <png.h>

#include "core/atomic_write.h"

namespace exao {

Result<void> write_exr(const AoImage& image, const std::string& path) {
  return write_atomically(path, [&](const std::string& temp) -> Result<void> {
    // The stream is ours so that its last, buffered bytes are checked: OpenEXR flushes in
    // destructors, where a failed write (a full disk) would pass in silence.
    std::ofstream stream(temp, std::ios::binary | std::ios::trunc);
    if (!stream) return fail(path + ": cannot open for writing: " + system_reason());
    try {
      Imf::StdOFStream out(stream, temp.c_str());
      Imf::Header header(image.width, image.height);
      header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
      header.channels().insert("A", Imf::Channel(Imf::FLOAT));
      const bool counts = !image.blocked.empty();
      if (counts) header.channels().insert("blocked", Imf::Channel(Imf::UINT));
      Imf::FrameBuffer frame;
      const std::size_t row = sizeof(float) * static_cast<std::size_t>(image.width);
      frame.insert("Y", Imf::Slice(Imf::FLOAT, (char*)image.ao.data(), sizeof(float), row));
      frame.insert("A", Imf::Slice(Imf::FLOAT, (char*)image.coverage.data(), sizeof(float), row));
      if (counts) {
        frame.insert("blocked", Imf::Slice(Imf::UINT, (char*)image.blocked.data(), sizeof(std::uint32_t),
                                           sizeof(std::uint32_t) * static_cast<std::size_t>(image.width)));
      }
      Imf::OutputFile file(out, header);
      file.setFrameBuffer(frame);
      file.writePixels(image.height);
    } catch (const std::exception& e) {
      return fail(path + ": cannot write OpenEXR: " + e.what());
    }
    stream.close();
    if (!stream) return fail(path + ": write failed: " + system_reason());
    return {};
  });
}

Result<void> write_png_bytes(std::span<const std::uint8_t> pixels, int width, int height, int channels,
                             const std::string& path) {
  return write_atomically(path, [&](const std::string& temp) -> Result<void> {
    std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(temp.c_str(), "wb"), std::fclose);
    if (!file) return fail(path + ": cannot open for writing: " + system_reason());
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
      png_destroy_write_struct(&png, &info);
      return fail(path + ": libpng could not start");
    }
    // libpng reports errors by longjmp; nothing with a destructor is created below this point.
    if (setjmp(png_jmpbuf(png))) {
      const int error = errno;  // libpng's fwrite failed, or libpng itself refused
      png_destroy_write_struct(&png, &info);
      errno = error;
      return fail(path + ": cannot write the PNG: " + system_reason("libpng failed"));
    }
    png_init_io(png, file.get());
    const int colour = channels == 1   ? PNG_COLOR_TYPE_GRAY
                       : channels == 2 ? PNG_COLOR_TYPE_GRAY_ALPHA
                       : channels == 3 ? PNG_COLOR_TYPE_RGB
                                       : PNG_COLOR_TYPE_RGBA;
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, colour,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    const std::size_t stride = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
    for (int y = 0; y < height; ++y) {
      png_write_row(png, const_cast<png_bytep>(pixels.data() + static_cast<std::size_t>(y) * stride));
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    if (std::fflush(file.get()) != 0) return fail(path + ": write failed: " + system_reason());
    if (std::fclose(file.release()) != 0) return fail(path + ": write failed: " + system_reason());
    return {};
  });
}

Result<void> write_png(const AoImage& image, const std::string& path) {
  const std::size_t pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  std::vector<std::uint8_t> bytes(2 * pixels);
  const auto to_byte = [](float v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
  };
  for (std::size_t p = 0; p < pixels; ++p) {
    bytes[2 * p] = to_byte(image.ao[p]);
    bytes[2 * p + 1] = to_byte(image.coverage[p]);
  }
  return write_png_bytes(bytes, image.width, image.height, 2, path);
}

}  // namespace exao
