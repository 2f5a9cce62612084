#include "png_writer.hpp"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace dynweigh::tools {
namespace {

// libpng reports errors by longjmp back to write_image (quietly: the caller says what failed).
void on_png_error(png_structp png, png_const_charp) { png_longjmp(png, 1); }
void on_png_warning(png_structp, png_const_charp) {}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

// libpng's write state, freed however the write ends.
class PngWrite {
 public:
  PngWrite() {
    png_ = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, on_png_error, on_png_warning);
    if (png_) info_ = png_create_info_struct(png_);
    if (!png_ || !info_) {
      png_destroy_write_struct(&png_, &info_);
      throw std::runtime_error("cannot start a PNG (out of memory)");
    }
  }
  ~PngWrite() { png_destroy_write_struct(&png_, &info_); }
  PngWrite(const PngWrite&) = delete;
  PngWrite& operator=(const PngWrite&) = delete;
  png_structp png() const { return png_; }
  png_infop info() const { return info_; }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

// Only libpng calls after the setjmp, so its longjmp skips no C++ destructor.
bool write_image(const PngWrite& write, std::FILE* file, png_uint_32 width, png_uint_32 height, png_bytepp rows) {
  if (setjmp(png_jmpbuf(write.png()))) return false;
  png_init_io(write.png(), file);
  png_set_IHDR(write.png(), write.info(), width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_filter(write.png(), 0, PNG_FILTER_NONE);  // screenshots of flat colours need no filter
  png_write_info(write.png(), write.info());
  png_write_image(write.png(), rows);
  png_write_end(write.png(), nullptr);
  return true;
}

}  // namespace

void write_png(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  const std::size_t row = std::size_t(width) * 3;
  if (width <= 0 || height <= 0 || rgb.size() != row * std::size_t(height)) throw std::runtime_error("bad image size");
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = const_cast<png_bytep>(rgb.data() + row * y);
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw std::runtime_error("cannot write " + path);
  const PngWrite write;
  if (!write_image(write, file.get(), png_uint_32(width), png_uint_32(height), rows.data()) ||
      std::fclose(file.release()) != 0) {
    throw std::runtime_error("cannot write " + path);
  }
}

}  // namespace dynweigh::tools
