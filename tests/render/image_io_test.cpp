// PNG and EXR writers checked with independent readers (libpng's and OpenEXR's own read APIs).
#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <png.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "../common/scratch_dir.h"
#include "image_io.h"

using namespace sphfx::render;

namespace {

std::string tempPath(const std::string& name) {
  return sphfx::test::scratchPath("image_io_" + name).string();
}

/// A 4x2 linear test image: known colours, a gradient in alpha, depth increasing along the row.
Image testImage() {
  Image img{4, 2, std::vector<float>(32), std::vector<float>(8)};
  const float colours[8][4] = {
      {0, 0, 0, 1}, {1, 1, 1, 1}, {0.5f, 0.5f, 0.5f, 1}, {0.2158f, 0.0f, 1.0f, 0.5f},
      {1, 0, 0, 0}, {0, 1, 0, 1}, {0, 0, 1, 1},          {2.0f, -1.0f, 0.0031308f, 1}};
  for (int i = 0; i < 8; ++i) {
    for (int c = 0; c < 4; ++c) img.rgba[i * 4 + c] = colours[i][c];
    img.depth[i] = 1.5f + float(i);
  }
  img.depth[7] = INFINITY;
  return img;
}

}  // namespace

TEST(ImageIo, SrgbEncodingOfKnownValues) {
  EXPECT_NEAR(linearToSrgb(0.5f), 0.735357f, 1e-5);
  EXPECT_NEAR(linearToSrgb(0.0031308f), 0.0404482f, 1e-5);  // the linear/power breakpoint
  EXPECT_EQ(linearToSrgb(-1), 0);
  EXPECT_EQ(linearToSrgb(2), 1);
  EXPECT_EQ(linearToSrgb(NAN), 0);
}

TEST(ImageIo, PngReadBackWithLibpng) {
  const std::string path = tempPath("a.png");
  writePng(path, encodeSrgb8(testImage()));
  // Independent reader: libpng's progressive row API, not the library's readPng.
  std::FILE* f = std::fopen(path.c_str(), "rb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_read_info(png, info);
  ASSERT_EQ(png_get_image_width(png, info), 4u);
  ASSERT_EQ(png_get_image_height(png, info), 2u);
  EXPECT_EQ(png_get_color_type(png, info), PNG_COLOR_TYPE_RGB);
  EXPECT_EQ(png_get_bit_depth(png, info), 8);
  int intent = -1;
  EXPECT_EQ(png_get_sRGB(png, info, &intent), PNG_INFO_sRGB);
  std::vector<png_byte> rows(2 * 12);
  png_read_row(png, &rows[0], nullptr);
  png_read_row(png, &rows[12], nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(f);
  const int expected[8][3] = {{0, 0, 0},   {255, 255, 255}, {188, 188, 188}, {128, 0, 255},
                              {255, 0, 0}, {0, 255, 0},     {0, 0, 255},     {255, 0, 10}};
  for (int i = 0; i < 8; ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(rows[i * 3 + c], expected[i][c]) << "pixel " << i << " channel " << c;
  EXPECT_EQ(readPng(path).rgb, std::vector<uint8_t>(rows.begin(), rows.end()));  // the library reader agrees
}

TEST(ImageIo, ExrReadBackWithOpenExr) {
  const Image img = testImage();
  const std::string path = tempPath("a.exr");
  writeExr(path, img);
  Imf::InputFile file(path.c_str());
  const Imf::ChannelList& ch = file.header().channels();
  for (const char* name : {"R", "G", "B", "A"}) {
    ASSERT_NE(ch.findChannel(name), nullptr) << name;
    EXPECT_EQ(ch.findChannel(name)->type, Imf::HALF) << name;
  }
  ASSERT_NE(ch.findChannel("Z"), nullptr);
  EXPECT_EQ(ch.findChannel("Z")->type, Imf::FLOAT);
  std::vector<float> rgba(32), z(8);
  Imf::FrameBuffer fb;
  const char* names[4] = {"R", "G", "B", "A"};
  for (int c = 0; c < 4; ++c)
    fb.insert(names[c],
              Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(&rgba[c]), 16, 64));  // converted on read
  fb.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(z.data()), 4, 16));
  file.setFrameBuffer(fb);
  file.readPixels(0, 1);
  for (size_t i = 0; i < rgba.size(); ++i)
    EXPECT_NEAR(rgba[i], img.rgba[i], std::abs(img.rgba[i]) * 1e-3 + 1e-6);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(z[i], img.depth[i]);
  EXPECT_TRUE(std::isinf(z[7]));
}

TEST(ImageIo, ContactSheetTilesThumbnails) {
  Image8 a{8, 4, std::vector<uint8_t>(96, 200)}, b{8, 4, std::vector<uint8_t>(96, 50)};
  const Image8 sheet = contactSheet({a, b, a}, 2);
  EXPECT_EQ(sheet.width, 2 * 8 + 3 * 4);
  EXPECT_EQ(sheet.height, 2 * 4 + 3 * 4);
  EXPECT_EQ(sheet.rgb[(size_t(4) * sheet.width + 4) * 3], 200);      // first thumbnail
  EXPECT_EQ(sheet.rgb[(size_t(4) * sheet.width + 4 + 12) * 3], 50);  // second, to its right
  EXPECT_EQ(sheet.rgb[(size_t(12) * sheet.width + 4) * 3], 200);     // third, next row
  EXPECT_EQ(sheet.rgb[(size_t(12) * sheet.width + 16) * 3], 24);     // empty cell: background
  EXPECT_EQ(downscale(Image8{640, 360, std::vector<uint8_t>(640 * 360 * 3, 7)}, 320).width, 320);
}
