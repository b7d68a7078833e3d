// Per photo: fit each face, render it, write its files and the contact sheet.
#include "libs/fit/photo_fit.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "libs/face/landmark_drawing.h"
#include "libs/fit/fit_outputs.h"
#include "libs/io/face_folders.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"

namespace fs = std::filesystem;

namespace facetool {

std::vector<DetectedFace> order_faces_by_size(std::vector<DetectedFace> faces) {
  std::stable_sort(faces.begin(), faces.end(),
                   [](const DetectedFace& a, const DetectedFace& b) { return a.size() > b.size(); });
  return faces;
}

PhotoFitter::PhotoFitter(std::shared_ptr<const FitBasis> basis, PhotoFitOptions options)
    : basis_(std::move(basis)), options_(options), sampler_(options.direction_count) {
  check(basis_ != nullptr, "PhotoFitter: no face model");
}

std::vector<FaceFit> PhotoFitter::fit(const RgbImage& photo, const std::vector<DetectedFace>& faces) const {
  std::vector<FaceFit> fits;
  for (const DetectedFace& face : faces) {
    LandmarkTarget target;
    target.landmarks = face.landmarks;
    target.width = photo.width;
    target.height = photo.height;
    fits.push_back(fit_landmarks(*basis_, target, options_.fit));
  }
  return fits;
}

void PhotoFitter::write(const std::string& folder, const RgbImage& photo, const std::vector<DetectedFace>& faces,
                        const std::vector<FaceFit>& fits, const std::string& source, PhotoFitTiming* timing) const {
  check(faces.size() == fits.size(), "PhotoFitter::write: ", faces.size(), " faces but ", fits.size(), " fits");
  std::vector<FitRendering> renderings;
  for (size_t k = 0; k < fits.size(); ++k) {
    renderings.push_back(render_fit(basis_->model(), fits[k], &sampler_, options_.render));
    const std::string face_folder = k == 0 ? folder : face_folder_name(folder, static_cast<int>(k));
    std::error_code ec;
    fs::create_directories(face_folder, ec);
    check(!ec, "cannot create output folder '", face_folder, "': ", ec.message());
    write_files_atomically(fit_product_files(face_folder, *basis_, fits[k], renderings.back(), faces[k], photo, source));
    if (timing) {
      timing->fit += fits[k].seconds;
      timing->geometry += renderings.back().seconds_geometry;
      timing->visibility += renderings.back().seconds_visibility;
      ++timing->faces;
    }
  }
  // face_<k>/ of an earlier fit of this photo that found more faces (fit.json lists this run's).
  remove_stale_face_folders(folder, std::max<int>(1, static_cast<int>(fits.size())));
  if (options_.contact_sheet && !fits.empty()) {
    const RgbImage row = fit_contact_sheet_row(photo, faces, fits, renderings, std::min(photo.width, 512));
    write_png_atomically((fs::path(folder) / "contact_sheet.png").string(), row, false);
  }
}

namespace {

void put(RgbImage& image, int x, int y, const float colour[3]) {
  if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
  float* p = image.at(x, y);
  for (int c = 0; c < 3; ++c) p[c] = colour[c];
}

void draw_line(RgbImage& image, Point2 a, Point2 b, const float colour[3]) {
  const int steps = static_cast<int>(std::ceil(std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)))) + 1;
  if (steps > 4096) return;
  for (int s = 0; s <= steps; ++s) {
    const double t = static_cast<double>(s) / steps;
    put(image, static_cast<int>(std::lround(a.x + t * (b.x - a.x))), static_cast<int>(std::lround(a.y + t * (b.y - a.y))), colour);
  }
}

// Planar channels of a photo-sized buffer shown over the photo (in sRGB), resized.
RgbImage overlay_panel(const RgbImage& photo, const std::vector<FitRendering>& renderings, bool normals, int width) {
  RgbImage panel = photo;
  for (float& v : panel.pixels) v = 0.35f * linear_to_srgb(v);
  const size_t plane = static_cast<size_t>(photo.width) * photo.height;
  const float unoccluded = static_cast<float>(2.0 * std::sqrt(3.14159265358979323846));
  for (auto it = renderings.rbegin(); it != renderings.rend(); ++it)
    for (size_t p = 0; p < plane; ++p) {
      if (!it->head[p]) continue;
      for (int c = 0; c < 3; ++c)
        panel.pixels[p * 3 + c] = normals ? 0.5f * (it->normal[c * plane + p] + 1.0f)
                                          : std::clamp(it->visibility[p] / unoccluded, 0.0f, 1.0f);
    }
  return resize_to_width(panel, width);
}

}  // namespace

RgbImage fit_contact_sheet_row(const RgbImage& photo, const std::vector<DetectedFace>& faces,
                               const std::vector<FaceFit>& fits, const std::vector<FitRendering>& renderings,
                               int width) {
  const double scale = static_cast<double>(width) / photo.width;
  RgbImage annotated = resize_to_width(photo, width);
  for (float& v : annotated.pixels) v = linear_to_srgb(v);
  const float wire[3] = {0.2f, 1.0f, 0.3f};
  for (size_t k = 0; k < fits.size(); ++k) {
    const FaceMesh& mesh = renderings[k].mesh;
    std::vector<Point2> projected(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const Point2 p = fits[k].project(mesh.positions[v]);
      projected[v] = {(p.x + 0.5) * scale - 0.5, (p.y + 0.5) * scale - 0.5};
    }
    // Every 7th face-region triangle's edges: a readable wireframe at contact-sheet size.
    for (size_t t = 0; t < mesh.triangles.size(); t += 7) {
      if (mesh.triangle_parts[t] != FacePart::kFace) continue;
      const auto& tri = mesh.triangles[t];
      for (int e = 0; e < 3; ++e) draw_line(annotated, projected[tri[e]], projected[tri[(e + 1) % 3]], wire);
    }
    draw_face(annotated, faces[k], scale);
  }
  const RgbImage normal = overlay_panel(photo, renderings, true, width);
  const RgbImage visibility = overlay_panel(photo, renderings, false, width);
  RgbImage row;
  const int gap = 2;
  row.width = 3 * width + 2 * gap;
  row.height = annotated.height;
  row.pixels.assign(static_cast<size_t>(row.width) * row.height * 3, 1.0f);
  const RgbImage* panels[3] = {&annotated, &normal, &visibility};
  for (int i = 0; i < 3; ++i)
    for (int y = 0; y < row.height && y < panels[i]->height; ++y)
      for (int x = 0; x < width; ++x)
        for (int c = 0; c < 3; ++c) row.at(i * (width + gap) + x, y)[c] = panels[i]->at(x, y)[c];
  return row;
}

}  // namespace facetool
