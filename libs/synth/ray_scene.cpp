// Embree 3 device and scene management for RayScene.
#include "libs/synth/ray_scene.h"

#include <embree3/rtcore.h>

#include <limits>
#include <mutex>

#include "core/util/error.h"

namespace facetool {
namespace {

const char* describe(RTCError error) {
  switch (error) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

// One Embree device for the process. BVH builds run on the calling thread only ("threads=1"):
// the generator already runs one sample per worker thread.
RTCDevice shared_device() {
  static std::once_flag once;
  static RTCDevice device = nullptr;
  std::call_once(once, [] {
    device = rtcNewDevice("threads=1,set_affinity=0");
    if (!device) fail("cannot create an Embree device: ", describe(rtcGetDeviceError(nullptr)));
  });
  return device;
}

}  // namespace

struct RayScene::Impl {
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
  }
};

RayScene::RayScene(const std::vector<Vec3f>& positions,
                   const std::vector<std::array<int32_t, 3>>& triangles)
    : impl_(std::make_unique<Impl>()) {
  check(!positions.empty() && !triangles.empty(), "RayScene: the mesh is empty");
  RTCDevice device = shared_device();
  impl_->scene = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
      positions.size()));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
      triangles.size()));
  check(vertices && indices, "Embree: cannot allocate the mesh buffers: ",
        describe(rtcGetDeviceError(device)));
  for (size_t v = 0; v < positions.size(); ++v)
    for (int k = 0; k < 3; ++k) vertices[3 * v + k] = positions[v][k];
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      check(triangles[t][k] >= 0 && static_cast<size_t>(triangles[t][k]) < positions.size(),
            "RayScene: triangle ", t, " uses vertex ", triangles[t][k], " of ", positions.size());
      indices[3 * t + k] = static_cast<uint32_t>(triangles[t][k]);
    }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_MEDIUM);
  rtcCommitScene(impl_->scene);
  const RTCError error = rtcGetDeviceError(device);
  check(error == RTC_ERROR_NONE, "Embree: building the scene failed: ", describe(error));
}

RayScene::~RayScene() = default;

RayScene::Hit RayScene::intersect(Vec3f origin, Vec3f direction) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query{};
  query.ray.org_x = origin.x;
  query.ray.org_y = origin.y;
  query.ray.org_z = origin.z;
  query.ray.dir_x = direction.x;
  query.ray.dir_y = direction.y;
  query.ray.dir_z = direction.z;
  query.ray.tnear = 0.0f;
  query.ray.tfar = std::numeric_limits<float>::infinity();
  query.ray.mask = 0xFFFFFFFFu;
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &query);
  Hit hit;
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.triangle = static_cast<int32_t>(query.hit.primID);
  hit.u = query.hit.u;
  hit.v = query.hit.v;
  hit.distance = query.ray.tfar;
  return hit;
}

uint32_t RayScene::occluded16(const Packet16& packet, float tnear) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) int valid[16];
  RTCRay16 rays;
  const float infinity = std::numeric_limits<float>::infinity();
  for (int k = 0; k < 16; ++k) {
    // Inactive lanes are masked (valid 0) and still get a finite ray: Embree may read them.
    const bool used = (packet.active >> k) & 1u;
    valid[k] = used ? -1 : 0;
    rays.org_x[k] = used ? packet.org_x[k] : 0.0f;
    rays.org_y[k] = used ? packet.org_y[k] : 0.0f;
    rays.org_z[k] = used ? packet.org_z[k] : 0.0f;
    rays.tnear[k] = tnear;
    rays.dir_x[k] = used ? packet.dir_x[k] : 0.0f;
    rays.dir_y[k] = used ? packet.dir_y[k] : 0.0f;
    rays.dir_z[k] = used ? packet.dir_z[k] : 1.0f;
    rays.time[k] = 0.0f;
    rays.tfar[k] = infinity;
    rays.mask[k] = 0xFFFFFFFFu;
    rays.id[k] = static_cast<unsigned>(k);
    rays.flags[k] = 0;
  }
  rtcOccluded16(valid, impl_->scene, &context, &rays);
  uint32_t blocked = 0;
  for (int k = 0; k < 16; ++k)
    if (((packet.active >> k) & 1u) && rays.tfar[k] < 0.0f) blocked |= 1u << k;  // hit: -inf
  return blocked;
}

}  // namespace facetool
