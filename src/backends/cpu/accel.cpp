#include "backends/cpu/accel.h"

#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "backends/backend_error.h"
#include "core/parallel.h"

namespace rl {

struct Accel::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {
void check_device(RTCDevice device, const char* what) {
  RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE) throw BackendError(std::string("Embree error while ") + what + " (code " + std::to_string(int(err)) + ")");
}
}  // namespace

Accel::Accel(const Scene& scene) : scene_(scene), impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice("threads=0");  // Embree builds with TBB's arena, no threads of its own
  if (!impl_->device) throw BackendError("cannot create the Embree device");
  impl_->scene = rtcNewScene(impl_->device);
  // An animated scene gets Embree's two-level structure (scene quality LOW), in which each
  // geometry has its own BVH built at its own quality: HIGH for what stands still, REFIT for what
  // moves, so that update() refits the moving geometries and rebuilds only the small top level.
  // (Embree uses per-geometry qualities only under a LOW scene quality.)
  const bool animated = scene_animated(scene);
  rtcSetSceneBuildQuality(impl_->scene, animated ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_HIGH);
  if (animated) rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_DYNAMIC);

  Bounds3 b;
  for (uint32_t mi = 0; mi < scene.meshes.size(); ++mi) {
    const TriangleMesh& m = scene.meshes[mi];
    RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Shared buffers: Embree reads the scene's arrays in place (Vec3 is 12 bytes; Embree reads
    // 16 bytes past the last vertex for SSE loads, so pad by copying into a padded buffer).
    float* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), m.positions.size()));
    for (size_t i = 0; i < m.positions.size(); ++i) {
      vb[3 * i + 0] = m.positions[i].x;
      vb[3 * i + 1] = m.positions[i].y;
      vb[3 * i + 2] = m.positions[i].z;
      b.extend(m.positions[i]);
    }
    unsigned* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                  3 * sizeof(unsigned), m.triangle_count()));
    std::copy(m.indices.begin(), m.indices.end(), ib);
    if (animated) rtcSetGeometryBuildQuality(g, m.animation >= 0 ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(g);
    unsigned id = rtcAttachGeometry(impl_->scene, g);
    rtcReleaseGeometry(g);
    if (id != mi) throw BackendError("unexpected Embree geometry id");
  }
  if (!scene.spheres.empty()) {
    RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    float* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                            4 * sizeof(float), scene.spheres.size()));
    for (size_t i = 0; i < scene.spheres.size(); ++i) {
      const Sphere& s = scene.spheres[i];
      vb[4 * i + 0] = s.center.x;
      vb[4 * i + 1] = s.center.y;
      vb[4 * i + 2] = s.center.z;
      vb[4 * i + 3] = s.radius;
      b.extend(s.center - Vec3(s.radius));
      b.extend(s.center + Vec3(s.radius));
    }
    rtcCommitGeometry(g);
    unsigned id = rtcAttachGeometry(impl_->scene, g);
    rtcReleaseGeometry(g);
    if (id != sphere_geom()) throw BackendError("unexpected Embree geometry id");
  }
  rtcCommitScene(impl_->scene);
  check_device(impl_->device, "building the BVH");
  animated_ = animated;
  view_data_ = SceneViewData(scene);
  view_ = view_data_.view();
  if (!b.empty()) {
    float extent = std::max(max_component(max(b.hi, -b.lo)), max_component(b.diagonal()));
    epsilon_ = std::max(1e-5f * extent, 1e-6f);
  }
}

void Accel::update() {
  if (!animated_) return;
  for (uint32_t mi = 0; mi < scene_.meshes.size(); ++mi) {
    const TriangleMesh& m = scene_.meshes[mi];
    if (m.animation < 0) continue;
    RTCGeometry g = rtcGetGeometry(impl_->scene, mi);
    float* vb = static_cast<float*>(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, 0));
    for (size_t i = 0; i < m.positions.size(); ++i) {
      vb[3 * i + 0] = m.positions[i].x;
      vb[3 * i + 1] = m.positions[i].y;
      vb[3 * i + 2] = m.positions[i].z;
    }
    rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(g);
  }
  if (std::any_of(scene_.spheres.begin(), scene_.spheres.end(), [](const Sphere& s) { return s.animation >= 0; })) {
    RTCGeometry g = rtcGetGeometry(impl_->scene, sphere_geom());
    float* vb = static_cast<float*>(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, 0));
    for (size_t i = 0; i < scene_.spheres.size(); ++i) {
      vb[4 * i + 0] = scene_.spheres[i].center.x;
      vb[4 * i + 1] = scene_.spheres[i].center.y;
      vb[4 * i + 2] = scene_.spheres[i].center.z;
    }
    rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(g);
  }
  rtcCommitScene(impl_->scene);
  check_device(impl_->device, "updating the BVH");
  view_data_ = SceneViewData(scene_);  // moved spheres' centres are copied into the view
  view_ = view_data_.view();
  ++generation_;
}

Accel::~Accel() = default;

namespace {
// The one guard in front of Embree is ray_queryable (ray_queries.h): Embree asserts on rays it
// rejects; the loaders refuse scenes that could produce such rays, and anything that still gets
// here (a NaN from a degenerate sample) hits nothing.
bool embree_safe(const Ray& r) { return ray_queryable(r); }

constexpr size_t kStreamChunk = 256;  // rays per Embree stream call (on the stack)

// A stream query's context (coherent: camera rays, which Embree traces as packets); the batch goes
// to the ray log first when one is set.
RTCIntersectContext stream_context(RayLog* log, std::span<const Ray> rays, bool any_hit, bool coherent) {
  if (log)
    for (const Ray& r : rays) log->add(r, any_hit);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return ctx;
}

// Every query fills Embree's ray and reads its hit through these two.
RTCRay to_rtc(const Ray& ray, bool safe) {
  RTCRay r;
  r.org_x = ray.o.x;
  r.org_y = ray.o.y;
  r.org_z = ray.o.z;
  r.dir_x = ray.d.x;
  r.dir_y = ray.d.y;
  r.dir_z = ray.d.z;
  r.tnear = ray.tmin;
  r.tfar = ray.tmax;
  if (!safe) {  // a ray Embree would assert on: an empty one that hits nothing (see embree_safe)
    r.org_x = r.org_y = r.org_z = 0;
    r.dir_x = 0, r.dir_y = 0, r.dir_z = 1;
    r.tnear = 0;
    r.tfar = -1;
  }
  r.time = 0;
  r.mask = 0xffffffffu;
  r.id = 0;
  r.flags = 0;
  return r;
}

Hit to_hit(const RTCRayHit& rh) {
  Hit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.t = rh.ray.tfar;
  h.geom = rh.hit.geomID;
  h.prim = rh.hit.primID;
  h.u = rh.hit.u;
  h.v = rh.hit.v;
  return h;
}
}  // namespace

struct RayLog::Impl {
  tbb::enumerable_thread_specific<std::vector<Ray>> closest, any_hit;
};
RayLog::RayLog() : impl_(std::make_unique<Impl>()) {}
RayLog::~RayLog() = default;
void RayLog::add(const Ray& ray, bool any_hit) { (any_hit ? impl_->any_hit : impl_->closest).local().push_back(ray); }
namespace {
std::vector<Ray> gather(const tbb::enumerable_thread_specific<std::vector<Ray>>& parts) {
  std::vector<Ray> all;
  for (const auto& part : parts) all.insert(all.end(), part.begin(), part.end());
  return all;
}
}  // namespace
std::vector<Ray> RayLog::closest() const { return gather(impl_->closest); }
std::vector<Ray> RayLog::any_hit() const { return gather(impl_->any_hit); }

bool Accel::intersect(const Ray& ray, Hit& hit) const {
  if (log_) log_->add(ray, false);
  if (!embree_safe(ray)) return false;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray = to_rtc(ray, true);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  hit = to_hit(rh);
  return hit.valid();
}

bool Accel::occluded(const Ray& ray) const {
  if (log_) log_->add(ray, true);
  if (!embree_safe(ray)) return false;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r = to_rtc(ray, true);
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar < 0;  // Embree sets tfar = -inf on a hit
}

void Accel::intersect(std::span<const Ray> rays, std::span<Hit> hits, bool coherent) const {
  RTCIntersectContext ctx = stream_context(log_, rays, false, coherent);
  RTCRayHit buf[kStreamChunk];
  for (size_t begin = 0; begin < rays.size(); begin += kStreamChunk) {
    const size_t n = std::min(kStreamChunk, rays.size() - begin);
    for (size_t i = 0; i < n; ++i) {
      const Ray& ray = rays[begin + i];
      buf[i].ray = to_rtc(ray, embree_safe(ray));
      buf[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
      buf[i].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect1M(impl_->scene, &ctx, buf, unsigned(n), sizeof(RTCRayHit));
    for (size_t i = 0; i < n; ++i) hits[begin + i] = to_hit(buf[i]);
  }
}

void Accel::occluded(std::span<const Ray> rays, std::span<uint8_t> blocked, bool coherent) const {
  RTCIntersectContext ctx = stream_context(log_, rays, true, coherent);
  RTCRay buf[kStreamChunk];
  for (size_t begin = 0; begin < rays.size(); begin += kStreamChunk) {
    const size_t n = std::min(kStreamChunk, rays.size() - begin);
    bool safe[kStreamChunk];
    for (size_t i = 0; i < n; ++i) {
      safe[i] = embree_safe(rays[begin + i]);
      buf[i] = to_rtc(rays[begin + i], safe[i]);
    }
    rtcOccluded1M(impl_->scene, &ctx, buf, unsigned(n), sizeof(RTCRay));
    for (size_t i = 0; i < n; ++i) blocked[begin + i] = safe[i] && buf[i].tfar < 0 ? 1 : 0;  // Embree: tfar = -inf on a hit
  }
}

namespace {
constexpr size_t kBatchChunk = 256;  // rays per parallel task of a batch
}  // namespace

void Accel::intersect_batch(std::span<const Ray> rays, std::span<Hit> hits, bool coherent) const {
  parallel_for_chunks(rays.size(), kBatchChunk, [&](size_t a, size_t b) { intersect(rays.subspan(a, b - a), hits.subspan(a, b - a), coherent); });
}

void Accel::occluded_batch(std::span<const Ray> rays, std::span<uint8_t> blocked) const {
  parallel_for_chunks(rays.size(), kBatchChunk, [&](size_t a, size_t b) { occluded(rays.subspan(a, b - a), blocked.subspan(a, b - a)); });
}

}  // namespace rl
