#include "frame/cpu_backend.h"

#include "scene/animation.h"

namespace rl {

std::vector<Mat4> motion_forward(const std::vector<Mat4>& back) {
  std::vector<Mat4> forward;
  forward.reserve(back.size());
  for (const Mat4& b : back) {
    Mat4 inv;
    forward.push_back(b.inverse(inv) ? inv : Mat4{});
  }
  return forward;
}

void CpuBackend::World::update(const RenderContext& ctx, const FrameInfo& frame) {
  fw_.world = path_world(ctx);
  const RayCounter counter{frame.stages ? slots_.get() : nullptr};  // counting while stage times are recorded
  fw_.tracer = EmbreeTracer{&ctx.accel, counter};
  fw_.has_previous = frame.previous_scene && frame.previous_accel;
  if (fw_.has_previous) {
    const Lights& lights = frame.previous_lights ? *frame.previous_lights : ctx.lights;
    fw_.previous_world = {frame.previous_accel->scene_view(), lights.view(), frame.previous_accel->ray_epsilon()};
    fw_.previous_tracer = EmbreeTracer{frame.previous_accel, counter};
  }
  fw_.has_previous_lights = frame.previous_lights != nullptr;
  if (fw_.has_previous_lights) fw_.previous_lights = frame.previous_lights->view();
  back_ = motion_back(ctx.scene, frame.index);
  forward_ = motion_forward(back_);
  fw_.back = back_.data(), fw_.forward = forward_.data(), fw_.animation_count = uint32_t(back_.size());
  if (!animated_known_) fw_.animated = scene_animated(ctx.scene), animated_known_ = true;  // it scans the scene: once
}

}  // namespace rl
