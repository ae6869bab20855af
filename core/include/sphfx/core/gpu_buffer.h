#pragma once
/// @file gpu_buffer.h
/// @brief A GL buffer object owned by a C++ object: storage, uploads, downloads, binding points.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sphfx {

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
};

}  // namespace sphfx
