#include "image_io.h"

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfRgbaFile.h>
#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <memory>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"

namespace sphfx::render {

float linearToSrgb(float v) {
  if (!(v > 0)) return 0;  // negatives and NaN
  if (v >= 1) return 1;
  return v <= 0.0031308f ? 12.92f * v : std::min(1.055f * std::pow(v, 1 / 2.4f) - 0.055f, 1.0f);
}

Image8 encodeSrgb8(const Image& image) {
  // A table over 16-bit linear steps: exact to the 8-bit output and much faster than pow per channel.
  static const std::array<uint8_t, 65536> table = [] {
    std::array<uint8_t, 65536> t{};
    for (size_t i = 0; i < t.size(); ++i) t[i] = uint8_t(std::lround(linearToSrgb(float(i) / 65535) * 255));
    return t;
  }();
  Image8 out{image.width, image.height, std::vector<uint8_t>(size_t(image.width) * image.height * 3)};
  const size_t n = size_t(image.width) * image.height;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = image.rgba[i * 4 + c];
      const float clamped = v > 0 ? (v < 1 ? v : 1) : 0;
      out.rgb[i * 3 + c] = table[size_t(std::lround(clamped * 65535))];
    }
  return out;
}

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

void writePngFile(const std::string& path, const Image8& image) {
  FilePtr file(std::fopen(path.c_str(), "wb"));
  if (!file) throw IoError("cannot write " + path);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw IoError("libpng: out of memory writing " + path);
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw IoError("libpng failed writing " + path);
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_set_compression_level(png, 3);  // render frames: favour speed over the last few percent
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y)
    png_write_row(png, const_cast<png_bytep>(&image.rgb[size_t(y) * image.width * 3]));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file.get()) != 0) throw IoError("cannot write " + path);
}

}  // namespace

void writePng(const std::string& path, const Image8& image) {
  writeFileAtomically(path, [&](const std::string& tmp) { writePngFile(tmp, image); });
}

Image8 readPng(const std::string& path) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str()))
    throw IoError("cannot read PNG " + path + ": " + img.message);
  img.format = PNG_FORMAT_RGB;
  Image8 out{int(img.width), int(img.height), std::vector<uint8_t>(PNG_IMAGE_SIZE(img))};
  if (!png_image_finish_read(&img, nullptr, out.rgb.data(), 0, nullptr)) {
    png_image_free(&img);
    throw IoError("cannot read PNG " + path + ": " + img.message);
  }
  return out;
}

void writeExr(const std::string& path, const Image& image) {
  const int w = image.width, h = image.height;
  std::vector<Imath::half> rgba(size_t(w) * h * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = Imath::half(image.rgba[i]);
  writeFileAtomically(path, [&](const std::string& tmp) {
    try {
      Imf::Header header(w, h);
      header.compression() = Imf::ZIP_COMPRESSION;
      Imf::FrameBuffer fb;
      const char* names[4] = {"R", "G", "B", "A"};
      for (int c = 0; c < 4; ++c) {
        header.channels().insert(names[c], Imf::Channel(Imf::HALF));
        fb.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(&rgba[c]), sizeof(Imath::half) * 4,
                                       sizeof(Imath::half) * 4 * w));
      }
      if (!image.depth.empty()) {
        header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        fb.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(image.depth.data())),
                                  sizeof(float), sizeof(float) * w));
      }
      Imf::OutputFile file(tmp.c_str(), header);
      file.setFrameBuffer(fb);
      file.writePixels(h);
    } catch (const std::exception& e) {
      throw IoError("cannot write EXR " + path + ": " + e.what());
    }
  });
}

Image readExrRgba(const std::string& path) {
  try {
    Imf::RgbaInputFile file(path.c_str());
    const Imath::Box2i dw = file.dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    std::vector<Imf::Rgba> px(size_t(w) * h);
    file.setFrameBuffer(px.data() - dw.min.x - size_t(dw.min.y) * w, 1, size_t(w));
    file.readPixels(dw.min.y, dw.max.y);
    Image out{w, h, std::vector<float>(px.size() * 4), {}};
    for (size_t i = 0; i < px.size(); ++i) {
      out.rgba[i * 4 + 0] = px[i].r, out.rgba[i * 4 + 1] = px[i].g;
      out.rgba[i * 4 + 2] = px[i].b, out.rgba[i * 4 + 3] = px[i].a;
    }
    return out;
  } catch (const std::exception& e) {
    throw IoError("cannot read EXR " + path + ": " + e.what());
  }
}

Image8 downscale(const Image8& image, int maxWidth) {
  const int factor = std::max(1, (image.width + maxWidth - 1) / maxWidth);
  const int w = std::max(1, image.width / factor), h = std::max(1, image.height / factor);
  Image8 out{w, h, std::vector<uint8_t>(size_t(w) * h * 3)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        // Averages 8-bit sRGB values: a thumbnail, where the gamma error of doing so does not matter.
        int sum = 0, count = 0;
        for (int dy = 0; dy < factor && y * factor + dy < image.height; ++dy)
          for (int dx = 0; dx < factor && x * factor + dx < image.width; ++dx, ++count)
            sum += image.rgb[(size_t(y * factor + dy) * image.width + x * factor + dx) * 3 + c];
        out.rgb[(size_t(y) * w + x) * 3 + c] = uint8_t((sum + count / 2) / count);
      }
  return out;
}

Image8 contactSheet(const std::vector<Image8>& thumbs, int columns) {
  if (thumbs.empty()) throw InputError("contact sheet: no frames");
  const int tw = thumbs[0].width, th = thumbs[0].height, gutter = 4;
  columns = std::clamp(columns, 1, int(thumbs.size()));
  const int rows = (int(thumbs.size()) + columns - 1) / columns;
  Image8 sheet{columns * (tw + gutter) + gutter, rows * (th + gutter) + gutter, {}};
  sheet.rgb.assign(size_t(sheet.width) * sheet.height * 3, 24);
  for (size_t i = 0; i < thumbs.size(); ++i) {
    if (thumbs[i].width != tw || thumbs[i].height != th)
      throw InputError("contact sheet: frame sizes differ");
    const int x0 = gutter + int(i % columns) * (tw + gutter), y0 = gutter + int(i / columns) * (th + gutter);
    for (int y = 0; y < th; ++y)
      std::copy_n(&thumbs[i].rgb[size_t(y) * tw * 3], size_t(tw) * 3,
                  &sheet.rgb[(size_t(y0 + y) * sheet.width + x0) * 3]);
  }
  return sheet;
}

}  // namespace sphfx::render
