// The Python module facetool._facetool (pybind11): photos as numpy arrays in, each face's
// albedo, normals, visibility, light, landmarks and mask out, in the crop and in the photo frame.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/backend/registry.h"
#include "libs/face/face_detector.h"
#include "libs/face/photo_reader.h"
#include "libs/inference/decomposer.h"
#include "libs/inference/model_loading.h"
#include "libs/io/image_io.h"
#include "core/util/terminal_text.h"
#include "libs/light/direction_light.h"
#include "libs/light/light_formats.h"
#include "libs/model/default_model.h"
#include "libs/photo/photo_outputs.h"
#include "libs/photo/photo_pipeline.h"
#include "libs/photo/relight_pipeline.h"
#include "libs/photo/session.h"
#include "libs/view/view_from_photo.h"
#include "libs/view/view_page.h"
#include "libs/view/view_presets.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/memory_budget.h"
#include "core/util/image_limits.h"

namespace py = pybind11;

namespace facetool {
namespace {

using FloatArray = py::array_t<float, py::array::c_style>;

// Planar [channels][h*w] values as a new (h, w, channels) float32 array.
FloatArray hwc_array(const float* planar, int channels, int h, int w) {
  FloatArray out({static_cast<py::ssize_t>(h), static_cast<py::ssize_t>(w), static_cast<py::ssize_t>(channels)});
  float* dst = out.mutable_data();
  const size_t plane = static_cast<size_t>(w) * h;
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < channels; ++c) dst[p * channels + c] = planar[c * plane + p];
  return out;
}

// One plane [h*w] as a new (h, w) float32 array.
FloatArray hw_array(const float* plane, int h, int w) {
  FloatArray out({static_cast<py::ssize_t>(h), static_cast<py::ssize_t>(w)});
  std::copy_n(plane, static_cast<size_t>(w) * h, out.mutable_data());
  return out;
}

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// A photo given as a numpy array: (height, width, 3) RGB, channels last. uint8 values are taken
// as sRGB-encoded and decoded to linear; float32/float64 values as linear RGB (finite).
RgbImage image_from_array(const py::handle& object, const char* what) {
  if (!py::isinstance<py::array>(object))
    throw py::type_error(std::string(what) + " must be a numpy array of shape (height, width, 3), not " +
                         py::str(py::type::of(object)).cast<std::string>());
  const py::array a = py::reinterpret_borrow<py::array>(object);
  if (a.ndim() != 3 || a.shape(2) != 3)
    throw py::value_error(std::string(what) + " must have shape (height, width, 3): RGB with the channels last; got shape " +
                          shape_text(a) + (a.ndim() == 3 && a.shape(0) == 3 ? " (channels first? use image.transpose(1, 2, 0))" : ""));
  const char kind = a.dtype().kind();
  const py::ssize_t item = a.dtype().itemsize();
  const bool is_uint8 = kind == 'u' && item == 1, is_float = kind == 'f' && (item == 4 || item == 8);
  if (!is_uint8 && !is_float)
    throw py::type_error(std::string(what) + " must be uint8 (sRGB) or float32/float64 (linear RGB); got dtype " +
                         py::str(a.dtype()).cast<std::string>());
  const py::ssize_t h = a.shape(0), w = a.shape(1);
  if (h < 1 || w < 1 || h > kMaxImageSide || w > kMaxImageSide ||
      static_cast<uint64_t>(h) * static_cast<uint64_t>(w) > kMaxImagePixels)
    throw py::value_error(std::string(what) + " is " + std::to_string(w) + "x" + std::to_string(h) +
                          " pixels; facetool takes 1 to " + std::to_string(kMaxImageSide) + " pixels a side and at most " +
                          std::to_string(kMaxImagePixels) + " pixels");
  RgbImage image;
  image.width = static_cast<int>(w);
  image.height = static_cast<int>(h);
  const std::string task = std::string("reading ") + what + " (" + std::to_string(w) + " x " + std::to_string(h) + ")";
  const uint64_t bytes = static_cast<uint64_t>(w) * h * 3 * sizeof(float);
  check_memory_budget(bytes, task);
  naming_out_of_memory(task, bytes, [&] { image.pixels.resize(static_cast<size_t>(w) * h * 3); });
  if (is_uint8) {
    // forcecast also copies arrays of any stride (slices, transposes) into C order.
    const auto c = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(a);
    const uint8_t* src = c.data();
    for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = srgb_to_linear(src[i] / 255.0f);
  } else {
    const auto c = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    const float* src = c.data();
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      if (!std::isfinite(src[i]))
        throw py::value_error(std::string(what) + " holds a non-finite value (NaN or infinity) at pixel (" +
                              std::to_string(i / 3 % w) + ", " + std::to_string(i / 3 / w) + ")");
      image.pixels[i] = src[i];
    }
  }
  return image;
}

// A light as 27 numbers (channel-major R0..R8 G0..G8 B0..B8) from a (3, 9) or (27,) array.
sh::RgbLight light_from_array(const py::handle& object) {
  if (!py::isinstance<py::array>(object) && !py::isinstance<py::sequence>(object))
    throw py::type_error("a light must be a numpy array of shape (3, 9) or (27,) (R, G, B rows of 9 SH coefficients)");
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!a) throw py::type_error("a light must be numbers: a (3, 9) or (27,) array");
  if (!((a.ndim() == 2 && a.shape(0) == 3 && a.shape(1) == 9) || (a.ndim() == 1 && a.shape(0) == 27)))
    throw py::value_error("a light must have shape (3, 9) or (27,) (R, G, B rows of 9 SH coefficients); got shape " +
                          shape_text(a));
  sh::RgbLight light{};
  for (int i = 0; i < sh::kLightCoeffCount; ++i) {
    light[i] = a.data()[i];
    if (!std::isfinite(light[i])) throw py::value_error("the light holds a non-finite value (NaN or infinity)");
    if (std::abs(light[i]) > light::kMaxLightCoefficient)
      throw py::value_error("the light holds " + std::to_string(light[i]) + "; its coefficients must lie within +-1e6");
  }
  return light;
}

py::array_t<double> light_array(const sh::RgbLight& light) {
  py::array_t<double> out({3, 9});
  std::copy(light.begin(), light.end(), out.mutable_data());
  return out;
}

py::array_t<double> landmarks_array(const Landmarks68& landmarks, const Similarity2* transform) {
  py::array_t<double> out({kLandmarkCount, 2});
  double* d = out.mutable_data();
  for (int i = 0; i < kLandmarkCount; ++i) {
    const Point2 p = transform ? transform->apply(landmarks[i]) : landmarks[i];
    d[i * 2] = p.x;
    d[i * 2 + 1] = p.y;
  }
  return out;
}

// A decomposed photo shared by its Photo and Face objects.
using SharedPhoto = std::shared_ptr<const DecomposedPhoto>;

struct Face {
  SharedPhoto photo;
  int index = 0;
  const FaceCrop& crop() const { return photo->crops[index]; }
  FloatArray planes(const std::vector<float>& all, int channels) const {
    const int s = photo->crop_size;
    return hwc_array(all.data() + static_cast<size_t>(index) * channels * s * s, channels, s, s);
  }
};

struct Photo {
  SharedPhoto photo;
  double feather = 3.0;   // the paste-back's, as infer's faces.json records them (for the view page)
  bool forehead = false;  // the face region, resolved
};

// The view page (libs/view) of `photo`, titled by its source's file name (as infer names its
// folder) or "photo": what `facetool view` writes for infer's folder of the same photo.
std::string view_page(const Photo& p) {
  for (PhotoLayer l : all_photo_layers())
    if (!p.photo->layers.made.has(l))
      throw Error(std::string("the view page shows every layer, and this photo's ") + photo_layer_name(l) +
                  " layer was not computed: decompose() it without layers=");
  std::string name = std::filesystem::path(p.photo->path).stem().string();
  if (name.empty()) name = "photo";
  const view::ViewPhoto photo = view::view_photo_from(*p.photo, name, p.feather, p.forehead);
  return view::view_page_html(photo, view::page_presets(photo, {}));
}

// A photo-level layer of `p`; facetool.Error naming decompose()'s layers= argument when it was not
// computed.
const std::vector<float>& made_layer(const Photo& p, PhotoLayer layer) {
  const PhotoLayers& layers = p.photo->layers;
  if (!layers.made.has(layer)) {
    std::string made;
    for (PhotoLayer l : all_photo_layers())
      if (layers.made.has(l)) made += std::string(made.empty() ? "" : ", ") + photo_layer_name(l);
    throw Error(std::string("the photo's ") + photo_layer_name(layer) + " layer was not computed: decompose() was given layers=[" +
                made + "]; add '" + photo_layer_name(layer) + "' to layers= (or leave layers= out for every layer)");
  }
  switch (layer) {
    case PhotoLayer::kAlbedo: return layers.albedo;
    case PhotoLayer::kNormal: return layers.normal;
    case PhotoLayer::kVisibility: return layers.visibility;
    case PhotoLayer::kShading: return layers.shading;
    case PhotoLayer::kReconstruction: return layers.reconstruction;
  }
  return layers.albedo;
}

// decompose()'s layers= argument: None (every layer), one name, or a sequence of names.
PhotoLayerSet layers_from_argument(const py::object& layers) {
  if (layers.is_none()) return PhotoLayerSet::all();
  std::vector<std::string> names;
  if (py::isinstance<py::str>(layers)) {
    names.push_back(layers.cast<std::string>());
  } else {
    if (!py::isinstance<py::sequence>(layers))
      throw py::type_error("layers must be None (every layer) or a list of layer names, not " +
                           py::str(py::type::of(layers)).cast<std::string>());
    for (const py::handle& item : layers) {
      if (!py::isinstance<py::str>(item))
        throw py::type_error("layers must be names (str), not " + py::str(py::type::of(item)).cast<std::string>());
      names.push_back(item.cast<std::string>());
    }
  }
  try {
    return parse_photo_layers(names, "layers");
  } catch (const Error& e) {
    throw py::value_error(e.what());
  }
}

class Model;

// A path from Python as facetool opens it: one with a NUL byte would be cut short there, so it is
// refused (ValueError naming `what`), as is an empty one.
const std::string& checked_path(const std::string& path, const char* what) {
  if (path.empty()) throw py::value_error(std::string(what) + ": an empty path");
  if (path.find('\0') != std::string::npos)
    throw py::value_error(std::string(what) + ": the path holds a NUL byte; no file has such a name");
  return path;
}

// Photo-pipeline options of decompose(), as keyword arguments.
PhotoInferOptions photo_options(int max_faces, double min_face_size, double min_score,
                                const std::string& face_region, double feather, int batch) {
  if (max_faces < 0) throw py::value_error("max_faces must be 0 (all) or more");
  if (!(min_face_size >= 0) || min_face_size > 1e6)
    throw py::value_error("min_face_size must be 0 (automatic) or a size in pixels up to 1e6");
  if (!(feather >= 0) || feather > 256) throw py::value_error("feather must be between 0 and 256 crop pixels");
  if (batch < 1 || batch > 1024) throw py::value_error("batch must be between 1 and 1024");
  if (!std::isfinite(min_score)) throw py::value_error("min_score must be a finite number");
  PhotoInferOptions o;
  o.detection.max_faces = max_faces;
  o.detection.min_face_size = min_face_size;
  o.detection.score_threshold = min_score;
  try {
    o.region = parse_face_region(face_region, "face_region");
  } catch (const Error& e) {
    throw py::value_error(e.what());
  }
  o.feather = feather;
  o.batch = batch;
  return o;
}

// A loaded model: a Session (libs/photo/session.h) behind a lock, with the landmark model chosen
// at load time.
class Model {
 public:
  Model(const std::string& weights, const std::string& backend, const std::string& renderer,
        const std::string& landmark_model, bool mirror_average, bool landmark_normals, bool light_gain,
        bool light_solve)
      : landmark_model_(landmark_model.empty() ? kDefaultLandmarkModel : landmark_model) {
    SessionOptions options;
    options.weights = weights;
    options.backend = backend;
    options.renderer = renderer;
    options.mirror_average = mirror_average;
    options.landmark_normals = landmark_normals;
    options.light_gain = light_gain;
    options.light_solve = light_solve;
    session_ = std::make_unique<Session>(options);
  }

  Photo decompose(RgbImage image, const std::string& source, PhotoInferOptions options) {
    std::lock_guard<std::mutex> lock(mutex_);
    options.landmark_model = landmark_model_;
    const std::string task = "decomposing a " + std::to_string(image.width) + " x " + std::to_string(image.height) + " photo";
    const uint64_t bytes = static_cast<uint64_t>(image.width) * image.height * 47 * sizeof(float);  // photo_pipeline's layers
    return naming_out_of_memory(task, bytes, [&] {
      return Photo{std::make_shared<const DecomposedPhoto>(session_->decompose(std::move(image), source, options)),
                   options.feather, session_->framed(options).extends_forehead()};
    });
  }

  RelitPhoto relight(const DecomposedPhoto& photo, const sh::RgbLight& light, const RelightSettings& settings) {
    std::lock_guard<std::mutex> lock(mutex_);
    return session_->relight(photo, light, settings);
  }

  const DecompositionModel& model() const { return session_->model(); }
  std::string backend_name() const { return session_->backend().name(); }

 private:
  std::mutex mutex_;
  std::string landmark_model_;
  std::unique_ptr<Session> session_;
};

relight::Mode mode_from_name(const std::string& mode) {
  if (mode == "ratio") return relight::Mode::Ratio;
  if (mode == "render") return relight::Mode::Render;
  throw py::value_error("mode must be 'ratio' (photo x new shading / old shading) or 'render' (albedo x new shading); got '" +
                        mode + "'");
}

}  // namespace
}  // namespace facetool

PYBIND11_MODULE(_facetool, m) {
  using namespace facetool;
  m.doc() = "facetool: intrinsic face decomposition (albedo, normals, SH visibility, SH light) of photos.";
  // facetool.Error with the message made printable and valid UTF-8 (a file's bytes quoted in it
  // would otherwise leave Python an empty message).
  static py::exception<Error> error_type(m, "Error", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const OutOfMemory& e) {  // "out of memory while <task> (needs ~N GB)"
      PyErr_SetString(PyExc_MemoryError, printable_text(e.what()).c_str());
    } catch (const Error& e) {
      error_type(printable_text(e.what()).c_str());
    }
  });
  m.attr("Error").attr("__doc__") = "A facetool failure (unreadable file, no face found, missing model or plugin); the message says what to do.";

  m.def("backends", &available_backends,
        "Names of the compute backends that work on this machine (\"cpu\" always; \"opencl\" with a device).");
  m.def("default_model_path", &default_model_path,
        "Path of the shipped model (facetool-v2.safetensors); raises facetool.Error naming the folders searched.");

  py::class_<Face>(m, "Face", "One face of a decomposed photo: crop-level results (crop frame) and where it lies in the photo.")
      .def_property_readonly("index", [](const Face& f) { return f.index; }, "Position among the photo's faces (best detection score first).")
      .def_property_readonly("score", [](const Face& f) { return f.crop().face.score; }, "Detector score (HOG margin).")
      .def_property_readonly("box", [](const Face& f) {
            const DetectedFace& d = f.crop().face;
            return py::make_tuple(d.left, d.top, d.right, d.bottom);
          }, "Detector box (left, top, right, bottom) in photo pixels.")
      .def_property_readonly("landmarks", [](const Face& f) { return landmarks_array(f.crop().face.landmarks, nullptr); },
                             "(68, 2) landmarks (x, y) in photo pixels (iBUG 300-W layout).")
      .def_property_readonly("landmarks_crop", [](const Face& f) {
            return landmarks_array(f.crop().face.landmarks, &f.crop().alignment.photo_to_crop);
          }, "(68, 2) landmarks in crop pixels.")
      .def_property_readonly("photo_to_crop", [](const Face& f) {
            const Similarity2& t = f.crop().alignment.photo_to_crop;
            py::array_t<double> out({2, 3});
            double* d = out.mutable_data();
            d[0] = t.a; d[1] = -t.b; d[2] = t.tx; d[3] = t.b; d[4] = t.a; d[5] = t.ty;
            return out;
          }, "(2, 3) similarity taking photo pixels (x, y, 1) to crop pixels.")
      .def_property_readonly("crop", [](const Face& f) {
            const int s = f.photo->crop_size;
            return hwc_array(f.crop().rgb.data(), 3, s, s);
          }, "(S, S, 3) the aligned crop the network saw, linear RGB.")
      .def_property_readonly("mask", [](const Face& f) {
            const int s = f.photo->crop_size;
            return hw_array(f.crop().mask.data(), s, s);
          }, "(S, S) face mask of the crop: 1 inside the landmarks' hull, 0 outside.")
      .def_property_readonly("albedo", [](const Face& f) { return f.planes(f.photo->decomposition.albedo, 3); },
                             "(S, S, 3) albedo, linear RGB in [0, 1].")
      .def_property_readonly("normal", [](const Face& f) { return f.planes(f.photo->decomposition.normal, 3); },
                             "(S, S, 3) unit normals in the crop frame (+X right, +Y up, +Z towards the camera).")
      .def_property_readonly("visibility", [](const Face& f) { return f.planes(f.photo->decomposition.visibility, 9); },
                             "(S, S, 9) SH coefficients of the visibility, crop frame.")
      .def_property_readonly("shading", [](const Face& f) { return f.planes(f.photo->decomposition.shading, 3); },
                             "(S, S, 3) shading; reconstruction = albedo * shading.")
      .def_property_readonly("reconstruction", [](const Face& f) { return f.planes(f.photo->decomposition.reconstruction, 3); },
                             "(S, S, 3) the re-rendered crop.")
      .def_property_readonly("light", [](const Face& f) {
            sh::RgbLight light{};
            for (int i = 0; i < sh::kLightCoeffCount; ++i)
              light[i] = f.photo->decomposition.light[static_cast<size_t>(f.index) * sh::kLightCoeffCount + i];
            return light_array(light);
          }, "(3, 9) SH light in the crop frame (rows R, G, B).")
      .def_property_readonly("light_photo", [](const Face& f) { return light_array(f.photo->photo_lights[f.index]); },
                             "(3, 9) SH light turned into the photo's frame.")
      .def_property_readonly("coverage", [](const Face& f) {
            const PasteRegion& r = f.photo->regions[f.index];
            const int w = f.photo->photo.width, h = f.photo->photo.height;
            FloatArray out({static_cast<py::ssize_t>(h), static_cast<py::ssize_t>(w)});
            float* d = out.mutable_data();
            std::fill_n(d, static_cast<size_t>(w) * h, 0.0f);
            for (int y = 0; y < r.height; ++y)
              for (int x = 0; x < r.width; ++x)
                d[static_cast<size_t>(r.y0 + y) * w + r.x0 + x] = r.alpha[static_cast<size_t>(y) * r.width + x];
            return out;
          }, "(H, W) this face's mask in the photo frame: its paste-back weight in [0, 1] (feathered edge).")
      .def("__repr__", [](const Face& f) {
        const DetectedFace& d = f.crop().face;
        return "<facetool.Face " + std::to_string(f.index) + " score " + std::to_string(d.score) + ", box (" +
               std::to_string(static_cast<int>(d.left)) + ", " + std::to_string(static_cast<int>(d.top)) + ", " +
               std::to_string(static_cast<int>(d.right)) + ", " + std::to_string(static_cast<int>(d.bottom)) + ")>";
      });

  py::class_<Photo>(m, "Photo", "A decomposed photo: its faces and the layers pasted back at the photo's resolution\n"
                               "(a layer left out of decompose(layers=...) raises facetool.Error).")
      .def_property_readonly("faces", [](const Photo& p) {
            std::vector<Face> faces;
            for (size_t k = 0; k < p.photo->crops.size(); ++k) faces.push_back(Face{p.photo, static_cast<int>(k)});
            return faces;
          }, "The faces, best detection score first.")
      .def_property_readonly("source", [](const Photo& p) { return p.photo->path; }, "The file it was read from, or \"\".")
      .def_property_readonly("image", [](const Photo& p) {
            const RgbImage& im = p.photo->photo;
            FloatArray out({static_cast<py::ssize_t>(im.height), static_cast<py::ssize_t>(im.width), py::ssize_t{3}});
            std::copy(im.pixels.begin(), im.pixels.end(), out.mutable_data());
            return out;
          }, "(H, W, 3) the photo, linear RGB.")
      .def_property_readonly("crop_size", [](const Photo& p) { return p.photo->crop_size; }, "S, the network's crop size.")
      .def_property_readonly("alpha", [](const Photo& p) {
            return hw_array(p.photo->layers.alpha.data(), p.photo->layers.height, p.photo->layers.width);
          }, "(H, W) face coverage in [0, 1]; the layers below are premultiplied by it.")
      .def_property_readonly("albedo", [](const Photo& p) {
            return hwc_array(made_layer(p, PhotoLayer::kAlbedo).data(), 3, p.photo->layers.height, p.photo->layers.width);
          }, "(H, W, 3) albedo pasted back (premultiplied by alpha).")
      .def_property_readonly("normal", [](const Photo& p) {
            return hwc_array(made_layer(p, PhotoLayer::kNormal).data(), 3, p.photo->layers.height, p.photo->layers.width);
          }, "(H, W, 3) normals in the photo frame (+X right, +Y up, +Z towards the viewer), premultiplied.")
      .def_property_readonly("visibility", [](const Photo& p) {
            return hwc_array(made_layer(p, PhotoLayer::kVisibility).data(), 9, p.photo->layers.height, p.photo->layers.width);
          }, "(H, W, 9) visibility SH coefficients in the photo frame, premultiplied.")
      .def_property_readonly("shading", [](const Photo& p) {
            return hwc_array(made_layer(p, PhotoLayer::kShading).data(), 3, p.photo->layers.height, p.photo->layers.width);
          }, "(H, W, 3) shading pasted back, premultiplied.")
      .def_property_readonly("reconstruction", [](const Photo& p) {
            return hwc_array(made_layer(p, PhotoLayer::kReconstruction).data(), 3, p.photo->layers.height, p.photo->layers.width);
          }, "(H, W, 3) re-rendered faces pasted back, premultiplied.")
      .def("view_html", [](const Photo& p) {
             std::string html;
             {
               py::gil_scoped_release release;
               html = view_page(p);
             }
             return py::bytes(html);
           },
           "The self-contained view page of this photo (docs/viewer.md) as UTF-8 bytes: the page `facetool view`\n"
           "writes for infer's folder of the same photo.")
      .def("write_view", [](const Photo& p, const std::string& path) {
             checked_path(path, "path");
             py::gil_scoped_release release;
             const std::string html = view_page(p);
             write_file_atomically(path, html.data(), html.size());
           },
           py::arg("path"), "Writes view_html() to `path` (atomically: a temporary file renamed).")
      .def("__len__", [](const Photo& p) { return p.photo->crops.size(); })
      .def("__repr__", [](const Photo& p) {
        return "<facetool.Photo " + std::to_string(p.photo->photo.width) + "x" + std::to_string(p.photo->photo.height) +
               ", " + std::to_string(p.photo->crops.size()) + " face(s)>";
      });

  py::class_<Model, std::shared_ptr<Model>>(m, "Model", "A decomposition model: network and renderer plugins on one backend, and the face detector.")
      .def(py::init([](const std::optional<std::string>& weights, const std::string& backend,
                       const std::string& renderer, const std::optional<std::string>& landmark_model,
                       bool mirror_average, bool landmark_normals, bool light_gain, bool light_solve) {
             if (weights) checked_path(*weights, "weights");
             if (landmark_model) checked_path(*landmark_model, "landmark_model");
             py::gil_scoped_release release;
             return std::make_shared<Model>(weights.value_or(""), backend, renderer, landmark_model.value_or(""),
                                            mirror_average, landmark_normals, light_gain, light_solve);
           }),
           py::arg("weights") = py::none(), py::arg("backend") = "cpu", py::arg("renderer") = "sh_renderer",
           py::arg("landmark_model") = py::none(), py::arg("mirror_average") = true,
           py::arg("landmark_normals") = true, py::arg("light_gain") = true, py::arg("light_solve") = true,
           "Loads `weights` (.safetensors; None: the shipped model) on `backend` (see facetool.backends()).\n"
           "`landmark_model`: dlib's 68-point predictor (None: Debian libdlib-data's; research use only).\n"
           "`mirror_average`: each face crop beside its mirror image, the answers averaged (as the facetool\n"
           "program; False: one network pass, as its --no-mirror-average).\n"
           "`landmark_normals`: the weights' landmark normal head blended into the network's normals (as the\n"
           "program; False: the network's alone, as its --no-landmark-normals, which also leaves the light's gain out).\n"
           "`light_gain`: each colour of the network's light scaled to render the face best in the head's face mask\n"
           "(as the program; False: the network's light as it is, as its --no-light-gain).\n"
           "`light_solve`: each face's light solved from its shading (a distant light plus ambient), the albedo\n"
           "following from the photo and that shading (as the program; False: the network's light, as its --no-light-solve).")
      .def("decompose", [](Model& model, const py::handle& image, int max_faces, double min_face_size, double min_score,
                           const std::string& face_region, double feather, int batch, const py::object& layers) {
             RgbImage photo = image_from_array(image, "image");
             PhotoInferOptions options = photo_options(max_faces, min_face_size, min_score, face_region, feather, batch);
             options.layers = layers_from_argument(layers);
             // A float image far above 1 is most likely 8-bit values given as floats: say so if no
             // face is found in it (it is taken as linear light in 0..1).
             float brightest = 0.0f;
             if (py::reinterpret_borrow<py::array>(image).dtype().kind() == 'f')
               for (const float v : photo.pixels) brightest = std::max(brightest, v);
             py::gil_scoped_release release;
             try {
               return model.decompose(std::move(photo), "", options);
             } catch (const Error& e) {
               if (brightest <= 2.0f || std::string(e.what()).find("no face") == std::string::npos) throw;
               throw Error(std::string(e.what()) + ". Float images are taken as linear RGB in 0..1 and this one reaches " +
                           std::to_string(brightest) + ": divide 8-bit values by 255 (and decode sRGB), or pass a uint8 array");
             }
           },
           py::arg("image"), py::kw_only(), py::arg("max_faces") = 0, py::arg("min_face_size") = 0.0,
           py::arg("min_score") = 0.25, py::arg("face_region") = "auto", py::arg("feather") = 3.0, py::arg("batch") = 8,
           py::arg("layers") = py::none(),
           "Finds every face of `image` ((H, W, 3) uint8 sRGB or float linear RGB), aligns it, decomposes it and\n"
           "pastes the results back. Returns a facetool.Photo; raises facetool.Error when no face is found.\n"
           "`layers`: the photo-level layers to paste back, a list of 'albedo', 'normal', 'visibility', 'shading',\n"
           "'reconstruction' (None: every one); asking the Photo for another raises facetool.Error. The faces'\n"
           "crop-level results and lights are computed whatever the list.")
      .def("decompose_file", [](Model& model, const std::string& path, int max_faces, double min_face_size,
                                double min_score, const std::string& face_region, double feather, int batch,
                                const py::object& layers) {
             PhotoInferOptions options = photo_options(max_faces, min_face_size, min_score, face_region, feather, batch);
             options.layers = layers_from_argument(layers);
             checked_path(path, "path");
             py::gil_scoped_release release;
             RgbImage photo;
             try {
               photo = read_photo(path);
             } catch (const Error& e) {
               throw Error("photo '" + path + "': " + e.what());
             }
             return model.decompose(std::move(photo), path, options);
           },
           py::arg("path"), py::kw_only(), py::arg("max_faces") = 0, py::arg("min_face_size") = 0.0,
           py::arg("min_score") = 0.25, py::arg("face_region") = "auto", py::arg("feather") = 3.0, py::arg("batch") = 8,
           py::arg("layers") = py::none(),
           "decompose() of an image file (8-bit files decoded from sRGB, EXR/HDR linear).")
      .def("relight", [](Model& model, const Photo& photo, const py::handle& light, const std::string& mode,
                         bool visibility, double ratio_epsilon) {
             RelightSettings settings;
             settings.mode = mode_from_name(mode);
             settings.visibility = visibility;
             if (!(ratio_epsilon > 0) || ratio_epsilon > 1) throw py::value_error("ratio_epsilon must be in (0, 1]");
             settings.ratio_epsilon = static_cast<float>(ratio_epsilon);
             const sh::RgbLight new_light = light_from_array(light);
             RelitPhoto relit;
             {
               py::gil_scoped_release release;
               relit = model.relight(*photo.photo, new_light, settings);
             }
             FloatArray out({static_cast<py::ssize_t>(relit.image.height), static_cast<py::ssize_t>(relit.image.width), py::ssize_t{3}});
             std::copy(relit.image.pixels.begin(), relit.image.pixels.end(), out.mutable_data());
             return out;
           },
           py::arg("photo"), py::arg("light"), py::kw_only(), py::arg("mode") = "ratio", py::arg("visibility") = true,
           py::arg("ratio_epsilon") = static_cast<double>(relight::kDefaultRatioEpsilon),
           "Replaces every face's light of a decomposed `photo` by `light` ((3, 9) SH, photo frame): one render and a\n"
           "paste-back, no network pass. mode 'ratio' keeps the photo's detail (photo x new / old shading), 'render'\n"
           "gives albedo x new shading. visibility=False: open hemisphere (no self-shadowing). Returns (H, W, 3) linear RGB.")
      .def_property_readonly("input_size", [](const Model& m) { return m.model().input_size; }, "The network's crop size S.")
      .def_property_readonly("architecture", [](const Model& m) { return m.model().architecture; }, "The network plugin's name.")
      .def_property_readonly("weights", [](const Model& m) { return m.model().weights_path; }, "The weights file loaded.")
      .def_property_readonly("backend", [](const Model& m) { return m.backend_name(); }, "The backend it runs on.")
      .def("__repr__", [](const Model& m) {
        return "<facetool.Model " + m.model().architecture + " " + std::to_string(m.model().input_size) + "x" +
               std::to_string(m.model().input_size) + " on " + m.backend_name() + " from '" + m.model().weights_path + "'>";
      });

  m.def("read_image", [](const std::string& path) {
          checked_path(path, "path");
          RgbImage im;
          {
            py::gil_scoped_release release;
            im = read_photo(path);
          }
          FloatArray out({static_cast<py::ssize_t>(im.height), static_cast<py::ssize_t>(im.width), py::ssize_t{3}});
          std::copy(im.pixels.begin(), im.pixels.end(), out.mutable_data());
          return out;
        }, py::arg("path"), "Reads an image file as (H, W, 3) float32 linear RGB (8-bit files decoded from sRGB).");
  m.def("light_from_sfsnet", [](const py::handle& values) {
          const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
          if (!a || a.size() != 27) throw py::value_error("an SfSNet light is 27 numbers");
          std::array<double, 27> v{};
          std::copy_n(a.data(), 27, v.begin());
          return light_array(light::from_sfsnet(v));
        }, py::arg("values"), "A facetool (3, 9) light from SfSNet's 27 numbers (docs/conventions.md).");
  m.def("light_to_sfsnet", [](const py::handle& light) {
          const std::array<double, 27> v = light::to_sfsnet(light_from_array(light));
          return py::array_t<double>(27, v.data());
        }, py::arg("light"), "SfSNet's 27 numbers of a facetool (3, 9) light.");
  m.def("light_from_dpr", [](const py::handle& values) {
          const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
          if (!a || a.size() != 9) throw py::value_error("a DPR light is 9 numbers");
          std::array<double, 9> v{};
          std::copy_n(a.data(), 9, v.begin());
          return light_array(light::from_dpr(v));
        }, py::arg("values"), "A facetool (3, 9) light (grey) from DPR's 9 numbers (docs/conventions.md).");
  m.def("light_from_direction", [](double azimuth, double elevation, double ambient, double intensity) {
          try {
            return light_array(light::light_from_direction(azimuth, elevation, ambient, intensity));
          } catch (const Error& e) {
            throw py::value_error(e.what());
          }
        }, py::arg("azimuth"), py::arg("elevation"), py::kw_only(), py::arg("ambient") = 0.1, py::arg("intensity") = 1.0,
        "A facetool (3, 9) white light: a distant light from `azimuth`, `elevation` (degrees, the photo's frame: 0, 0\n"
        "is the camera's position, a positive azimuth to the viewer's right, a positive elevation up) plus a uniform\n"
        "`ambient`; with albedo 1 and no occlusion it shades a surface ambient + intensity max(0, n.l), as the\n"
        "program's `light from-direction` and `relight --light-direction`.");
  m.def("light_to_dpr", [](const py::handle& light) {
          const std::array<double, 9> v = light::to_dpr(light_from_array(light));
          return py::array_t<double>(9, v.data());
        }, py::arg("light"), "DPR's 9 numbers of a facetool (3, 9) light (Rec. 601 luma of R, G, B).");
  m.def("read_light", [](const std::string& path, const std::optional<std::string>& format) {
          checked_path(path, "path");
          if (format) {
            const light::Format f = light::format_from_name(*format);
            return light_array(light::read_light(path, &f).light);
          }
          return light_array(light::read_light(path).light);
        }, py::arg("path"), py::arg("format") = py::none(),
        "Reads a light file (facetool .json, SfSNet 27 values, DPR 9 values; format guessed unless given) as (3, 9).");
}
