// Encoding pictures in memory through OpenImageIO's IOVecOutput proxy.
#include "libs/io/image_encoding.h"

#include <OpenImageIO/filesystem.h>

#include "core/util/error.h"

namespace facetool {

namespace OIIO = OIIO_NAMESPACE;

std::vector<unsigned char> encode_image(const std::string& path, const char* format,
                                        const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                                        const void* pixels) {
  auto output = OIIO::ImageOutput::create(format);
  check(output != nullptr, "cannot write '", path, "': OpenImageIO has no ", format,
        " writer (", OIIO::geterror(), ")");
  check(output->supports("ioproxy"), "cannot write '", path, "': OpenImageIO's ", format,
        " writer cannot write to memory (OpenImageIO too old?)");
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  OIIO::ImageSpec with_proxy = spec;
  void* proxy_pointer = &proxy;
  with_proxy.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_pointer);
  // The file name only tells OpenImageIO the format; the bytes go to `proxy`.
  if (!output->open(path, with_proxy) || !output->write_image(type, pixels) || !output->close())
    fail("cannot write '", path, "': OpenImageIO could not encode it: ", output->geterror());
  check(!bytes.empty(), "cannot write '", path, "': OpenImageIO produced no bytes");
  return bytes;
}

}  // namespace facetool
