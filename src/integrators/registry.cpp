// The registry: one row per algorithm (frame/integrator.h), each algorithm's entry points declared
// here and defined in its folder -- <algo>.cpp for the CPU and cpu-bvh backends, <algo>.cu for
// CUDA (built with -DRESTIR_CUDA=ON).
#include <fmt/format.h>

#include "backends/cuda/cuda_queries.h"
#include "frame/integrator.h"

namespace rl {

std::unique_ptr<Integrator> make_path_tracer(const RenderContext& ctx);
std::unique_ptr<Integrator> make_restir_di(const RenderContext& ctx);
std::unique_ptr<Integrator> make_restir_gi(const RenderContext& ctx);
std::unique_ptr<Integrator> make_restir_pt(const RenderContext& ctx);
std::unique_ptr<Integrator> make_ssr(const RenderContext& ctx);
void check_path_tracer(const RenderContext& ctx);
void check_restir_di(const RenderContext& ctx);
void check_restir_gi(const RenderContext& ctx);
void check_restir_pt(const RenderContext& ctx);
void check_ssr(const RenderContext& ctx);
#ifdef RESTIR_HAVE_CUDA
std::unique_ptr<Integrator> make_path_tracer_cuda(const RenderContext& ctx);
std::unique_ptr<Integrator> make_restir_di_cuda(const RenderContext& ctx);
std::unique_ptr<Integrator> make_restir_gi_cuda(const RenderContext& ctx);
std::unique_ptr<Integrator> make_restir_pt_cuda(const RenderContext& ctx);
std::unique_ptr<Integrator> make_ssr_cuda(const RenderContext& ctx);
#define RL_CUDA_MAKER(f) &f
#else
#define RL_CUDA_MAKER(f) nullptr
#endif

const std::vector<IntegratorInfo>& integrator_registry() {
  static const std::vector<IntegratorInfo> registry = {
      {"pt", "reference path tracer: NEE + MIS, Russian roulette (path.*)", "path", &check_path_tracer, &make_path_tracer,
       RL_CUDA_MAKER(make_path_tracer_cuda)},
      {"restir-di", "ReSTIR DI, direct lighting with temporal and spatial reuse (di.*)", "di", &check_restir_di, &make_restir_di,
       RL_CUDA_MAKER(make_restir_di_cuda)},
      {"restir-gi", "ReSTIR GI, reuse of secondary hits with cached radiance, reconnection shift (gi.*)", "path gi", &check_restir_gi,
       &make_restir_gi, RL_CUDA_MAKER(make_restir_gi_cuda)},
      {"restir-pt", "ReSTIR PT, path reuse with reconnection / random replay / hybrid shifts (pt.*)", "path pt di", &check_restir_pt,
       &make_restir_pt, RL_CUDA_MAKER(make_restir_pt_cuda)},
      {"ssr", "screen-space reflections: direct light plus reflections marched in the depth buffer (ssr.*); biased by design", "ssr path",
       &check_ssr, &make_ssr, RL_CUDA_MAKER(make_ssr_cuda)},
  };
  return registry;
}

namespace {
// The words of a space-separated list ("path pt di").
std::vector<std::string_view> words(std::string_view list) {
  std::vector<std::string_view> out;
  for (size_t at = 0; at < list.size();) {
    const size_t end = std::min(list.find(' ', at), list.size());
    if (end > at) out.push_back(list.substr(at, end - at));
    at = end + 1;
  }
  return out;
}
}  // namespace

bool IntegratorInfo::reads_group(std::string_view group) const {
  for (std::string_view g : words(reads))
    if (g == group) return true;
  return false;
}

void refuse_debug_views(const RenderContext& ctx, const char* why) {
  if (ctx.options.render.debug_view != DebugView::none) throw OptionError(std::string("render.debug_view: ") + why);
}

void refuse_reconnection_depth(const RenderContext& ctx, const char* why) {
  if (ctx.options.render.debug_view == DebugView::reconnection_depth)
    throw OptionError(std::string("render.debug_view: reconnection-depth belongs to restir-pt") + why);
}

const IntegratorInfo& find_integrator(const std::string& name) {
  std::string known;
  for (const auto& info : integrator_registry()) {
    if (name == info.name) return info;
    known += known.empty() ? "" : ", ";
    known += info.name;
  }
  throw OptionError("unknown integrator '" + name + "' (known: " + known + ")");
}

void check_option_groups(const Options& o) {
  const IntegratorInfo& info = find_integrator(o.integrator);
  for (const std::string& key : o.explicit_keys) {
    const size_t dot = key.find('.');
    if (dot == std::string::npos) continue;  // "integrator"
    const std::string group = key.substr(0, dot);
    // denoise.*: the post-process stage after any integrator (src/post/).
    if (group == "film" || group == "render" || group == "output" || group == "denoise" || info.reads_group(group)) continue;
    const std::string all = std::string(info.reads) + " film render denoise output";
    std::string groups;
    for (std::string_view g : words(all))
      groups += (groups.empty() ? "" : ", ") + std::string(g) + ".*";
    throw OptionError(fmt::format("option '{}' is not read by the integrator {} (it reads {}): remove it, or set it only where "
                                  "the integrator reads it (a study axis value null leaves a key unset)",
                                  key, o.integrator, groups));
  }
}

std::unique_ptr<Integrator> make_integrator(const std::string& name, const RenderContext& ctx) {
  const IntegratorInfo& info = find_integrator(name);
  if (info.check) info.check(ctx);
  if (ctx.options.render.backend != Backend::cuda) return info.make(ctx);
  if (!info.make_cuda) {
    const std::string why = cuda_unavailable_reason();
    throw OptionError(fmt::format("render.backend = cuda: {}", why.empty() ? name + " does not run on the CUDA backend" : why));
  }
  try {
    return info.make_cuda(ctx);
  } catch (const OptionError&) {
    throw;
  } catch (const std::runtime_error& e) {  // the device (BackendError: missing, busy, out of memory) or the CUDA runtime
    throw OptionError(std::string("render.backend = cuda: ") + e.what());
  }
}

}  // namespace rl
