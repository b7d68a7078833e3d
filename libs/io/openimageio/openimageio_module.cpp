// facetool_openimageio.so: image files read, and animated GIFs written, through OpenImageIO.
#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>
#include <vector>

#include "core/util/error.h"
#include "libs/io/openimageio_module.h"

namespace facetool {
namespace {

namespace OIIO = OIIO_NAMESPACE;

class OpenImageIoReader final : public ImageFileReader {
 public:
  OpenImageIoReader(std::string path, std::string kind, std::unique_ptr<OIIO::ImageInput> input)
      : path_(std::move(path)), kind_(std::move(kind)), input_(std::move(input)) {
    const OIIO::ImageSpec& spec = input_->spec();
    header_.width = spec.width;
    header_.height = spec.height;
    header_.channels = spec.nchannels;
    header_.format = input_->format_name();
    header_.floating = spec.format.is_floating_point();
    header_.eight_bit = spec.format == OIIO::TypeDesc::UINT8;
    header_.orientation = spec.get_int_attribute("Orientation", 1);
    header_.channel_names = spec.channelnames;
    for (const OIIO::ParamValue& attribute : spec.extra_attribs)
      if (attribute.type() == OIIO::TypeDesc::STRING)
        header_.attributes.emplace_back(attribute.name().string(), attribute.get_string());
  }

  const ImageFileHeader& header() const override { return header_; }
  void read_bytes(uint8_t* out) override { read(OIIO::TypeDesc::UINT8, out); }
  void read_floats(float* out) override { read(OIIO::TypeDesc::FLOAT, out); }

 private:
  void read(OIIO::TypeDesc type, void* out) {
    if (!input_->read_image(0, 0, 0, header_.channels, type, out))
      fail("cannot read the pixels of ", kind_, " '", path_, "': ", input_->geterror(),
           " (the file is truncated or damaged: replace or regenerate it)");
    input_->close();
  }

  std::string path_;
  std::string kind_;
  std::unique_ptr<OIIO::ImageInput> input_;
  ImageFileHeader header_;
};

std::unique_ptr<ImageFileReader> open_reader(const std::string& path, const std::string& kind) {
  // Alpha is dropped by every caller, so colours are read as stored: OpenImageIO would otherwise
  // multiply them by alpha (a half-transparent face comes out darker).
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open(path, &config);
  if (!input)
    fail("cannot read ", kind, " '", path, "': ", OIIO::geterror(),
         " (a damaged file, or a format OpenImageIO cannot read: replace or regenerate it)");
  return std::make_unique<OpenImageIoReader>(path, kind, std::move(input));
}

void write_gif(const std::string& path, int width, int height, const std::vector<std::vector<uint8_t>>& frames,
               int frames_per_second) {
  // `path` may be a temporary name without a .gif extension, so the format is named explicitly.
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("gif");
  check(out != nullptr, "cannot write animated GIF '", path, "': this OpenImageIO has no GIF "
        "writer (build it with giflib)");
  check(out->supports("multiimage") && out->supports("appendsubimage"),
        "cannot write animated GIF '", path, "': OpenImageIO's GIF writer cannot append frames");
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  const int rate[2] = {frames_per_second, 1};
  spec.attribute("FramesPerSecond", OIIO::TypeRational, rate);
  spec.attribute("gif:LoopCount", 0);
  std::vector<OIIO::ImageSpec> specs(frames.size(), spec);
  check(out->open(path, static_cast<int>(specs.size()), specs.data()), "cannot write animated GIF '",
        path, "': ", out->geterror());
  for (size_t k = 0; k < frames.size(); ++k) {
    if (k > 0)
      check(out->open(path, spec, OIIO::ImageOutput::AppendSubimage), "cannot append frame ", k,
            " to animated GIF '", path, "': ", out->geterror());
    check(out->write_image(OIIO::TypeDesc::UINT8, frames[k].data()), "cannot write frame ", k,
          " of animated GIF '", path, "': ", out->geterror());
  }
  check(out->close(), "cannot finish animated GIF '", path, "': ", out->geterror());
}

}  // namespace
}  // namespace facetool

extern "C" __attribute__((visibility("default"))) const facetool::OpenImageIoModule* facetool_openimageio_module() {
  static const facetool::OpenImageIoModule module = [] {
    facetool::OpenImageIoModule m;
    m.open = &facetool::open_reader;
    m.write_gif = &facetool::write_gif;
    return m;
  }();
  return &module;
}
