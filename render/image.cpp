#include "render/image.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#ifdef APICLAB_HAVE_ZLIB
#include <zlib.h>

namespace {
// zlib deflates faster than stb's own compressor, into smaller files.
unsigned char* deflate_with_zlib(unsigned char* data, int length, int* out_length, int) {
  uLongf size = compressBound(uLong(length));
  auto* out = static_cast<unsigned char*>(std::malloc(size));
  if (out && compress2(out, &size, data, uLong(length), 4) == Z_OK) {
    *out_length = int(size);
    return out;
  }
  std::free(out);
  return nullptr;
}
}  // namespace

#define STBIW_ZLIB_COMPRESS deflate_with_zlib
#endif
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

namespace apiclab::render {

namespace {

// Writes `bytes` to `path`.part, checked to the last byte and the close, then renames it: the
// PNG is whole or absent (stb's own file writer checks neither the write nor the close).
void write_whole(const std::string& path, const unsigned char* bytes, std::size_t size) {
  const std::string temp = path + ".part";
  const auto fail = [&](int error) {
    std::remove(temp.c_str());
    throw std::runtime_error("cannot write " + path + ": " + std::strerror(error ? error : EIO));
  };
  errno = 0;
  std::FILE* f = std::fopen(temp.c_str(), "wb");
  if (!f) fail(errno);
  int error = std::fwrite(bytes, 1, size, f) == size ? 0 : errno;
  errno = 0;
  if (std::fclose(f) != 0 && error == 0) error = errno ? errno : EIO;
  if (error == 0 && std::rename(temp.c_str(), path.c_str()) != 0) error = errno ? errno : EIO;
  if (error != 0) fail(error);
}

}  // namespace

void write_png(const Image& image, const std::string& path) {
  // Unfiltered rows: trying all five filters per row costs more than it saves here.
  stbi_write_force_png_filter = 0;
  int size = 0;
  unsigned char* png = stbi_write_png_to_mem(image.rgba.data(), image.width * 4, image.width,
                                             image.height, 4, &size);
  if (!png) throw std::runtime_error("cannot write " + path + ": PNG encoding failed");
  try {
    write_whole(path, png, std::size_t(size));
  } catch (...) {
    STBIW_FREE(png);
    throw;
  }
  STBIW_FREE(png);
}

Image read_png(const std::string& path) {
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
  if (!data) throw std::runtime_error("cannot read " + path + ": " + stbi_failure_reason());
  Image image(w, h);
  std::copy(data, data + image.rgba.size(), image.rgba.begin());
  stbi_image_free(data);
  return image;
}

ImageDifference compare_images(const Image& reference, const Image& actual, int tolerance) {
  ImageDifference d;
  if (reference.width != actual.width || reference.height != actual.height) {
    d.differing_pixels =
        std::max(long(reference.width) * reference.height, long(actual.width) * actual.height);
    d.largest = 255;
    d.visual = actual;
    return d;
  }
  d.visual = Image(reference.width, reference.height);
  for (int y = 0; y < reference.height; ++y)
    for (int x = 0; x < reference.width; ++x) {
      const std::uint8_t* a = reference.pixel(x, y);
      const std::uint8_t* b = actual.pixel(x, y);
      int largest = 0;
      for (int c = 0; c < 4; ++c) largest = std::max(largest, std::abs(int(a[c]) - int(b[c])));
      d.largest = std::max(d.largest, largest);
      std::uint8_t* v = d.visual.pixel(x, y);
      if (largest > tolerance) {
        ++d.differing_pixels;
        v[0] = 255, v[1] = 0, v[2] = 0;
      } else {
        // Faded reference, so the red pixels can be located in the picture.
        std::uint8_t grey = std::uint8_t(180 + (a[0] + a[1] + a[2]) / 3 * 75 / 255);
        v[0] = v[1] = v[2] = grey;
      }
      v[3] = 255;
    }
  return d;
}

}  // namespace apiclab::render
