#pragma once
/// @file gpu_buffer.h
/// @brief A GL buffer object owned by a C++ object: storage, uploads, downloads, binding points.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sphfx {

/// Texels a buffer texture may hold in the current context (GL_MAX_TEXTURE_BUFFER_SIZE).
size_t maxTextureBufferTexels();

class GpuBuffer {
 public:
  GpuBuffer() = default;
  /// Allocates `bytes` of storage (contents undefined). Needs a current context.
  explicit GpuBuffer(size_t bytes);
  ~GpuBuffer();
  GpuBuffer(GpuBuffer&& other) noexcept;
  GpuBuffer& operator=(GpuBuffer&& other) noexcept;
  GpuBuffer(const GpuBuffer&) = delete;
  GpuBuffer& operator=(const GpuBuffer&) = delete;

  /// Reallocates to `bytes` if the size differs (contents lost).
  void resize(size_t bytes);
  void upload(const void* data, size_t bytes, size_t offset = 0);
  void download(void* data, size_t bytes, size_t offset = 0) const;
  /// Sets every 32-bit word to `value`.
  void fill(uint32_t value);
  /// Binds to an indexed shader storage binding point.
  void bindStorage(uint32_t binding) const;
  /// Binds to an indexed uniform binding point.
  void bindUniform(uint32_t binding) const;
  /// Binds a read-only view of the buffer as a buffer texture (GLSL samplerBuffer/usamplerBuffer, read
  /// with texelFetch) to texture unit `unit`, texels of `format` (GL_RGBA32F, GL_RG32F, GL_R32F or
  /// GL_R32UI). The view is made on first use and follows resize(). Shader writes to the buffer need
  /// GL_TEXTURE_FETCH_BARRIER_BIT before a texel fetch sees them.
  /// @throws GLError for another format, or if the buffer holds more texels than the context's
  /// GL_MAX_TEXTURE_BUFFER_SIZE (both named in the message).
  void bindTexture(uint32_t unit, uint32_t format) const;

  template <class T>
  void uploadVector(const std::vector<T>& v) {
    if (v.size() * sizeof(T) > bytes_) resize(v.size() * sizeof(T));
    upload(v.data(), v.size() * sizeof(T));
  }
  template <class T>
  std::vector<T> downloadVector(size_t count) const {
    std::vector<T> v(count);
    download(v.data(), count * sizeof(T));
    return v;
  }

  uint32_t id() const { return id_; }
  size_t size() const { return bytes_; }

 private:
  uint32_t id_ = 0;
  size_t bytes_ = 0;
  // The buffer texture of bindTexture(): its name, format and the size it was attached at.
  mutable uint32_t texture_ = 0, textureFormat_ = 0;
  mutable size_t textureBytes_ = 0;
  void release();
};

}  // namespace sphfx
