#pragma once
/// @file image_io.h
/// @brief Rendered images in memory and on disk: linear float RGBA + camera depth, written as 8-bit sRGB
/// PNG (libpng) or half RGBA + float Z OpenEXR; contact sheets.

#include <cstdint>
#include <string>
#include <vector>

namespace sphfx::render {

/// A rendered frame, top row first (image order, not GL order).
struct Image {
  int width = 0;
  int height = 0;
  /// Linear (scene-referred) RGBA, 4 floats per pixel. Alpha is the MSAA coverage of geometry
  /// (0 where only the sky is seen).
  std::vector<float> rgba;
  /// Camera depth per pixel: distance along the view axis in metres; +infinity where nothing is hit.
  /// Empty when not read back.
  std::vector<float> depth;

  const float* pixel(int x, int y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};

/// 8-bit sRGB image, RGB, top row first.
struct Image8 {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;
};

/// The sRGB transfer function (IEC 61966-2-1) of a linear value, clamped to [0, 1].
float linearToSrgb(float linear);
/// Encodes a linear image to 8-bit sRGB (alpha dropped: the sky is part of the picture).
Image8 encodeSrgb8(const Image& image);

/// Writes an 8-bit sRGB PNG (with an sRGB chunk) atomically. @throws IoError.
void writePng(const std::string& path, const Image8& image);
/// Reads an 8-bit RGB or RGBA PNG (alpha dropped, palette/grey expanded). @throws IoError.
Image8 readPng(const std::string& path);
/// Writes half-float RGBA and float Z (when the image has depth) as an OpenEXR file atomically.
/// @throws IoError.
void writeExr(const std::string& path, const Image& image);
/// Reads the RGBA channels of an OpenEXR file as linear floats (depth left empty). @throws IoError.
Image readExrRgba(const std::string& path);

/// Downscales by box filtering so that the width is at most `maxWidth` (never upscales).
Image8 downscale(const Image8& image, int maxWidth);
/// Tiles `thumbs` (same size) left to right, top to bottom, `columns` per row, with a thin dark gutter.
/// @throws InputError if `thumbs` is empty or sizes differ.
Image8 contactSheet(const std::vector<Image8>& thumbs, int columns);

}  // namespace sphfx::render
