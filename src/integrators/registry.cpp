#include "frame/integrator.h"

namespace rl {

std::unique_ptr<Integrator> make_path_tracer(const RenderContext& ctx);
std::unique_ptr<Integrator> make_restir_di(const RenderContext& ctx);
std::unique_ptr<Integrator> make_restir_gi(const RenderContext& ctx);
std::unique_ptr<Integrator> make_restir_pt(const RenderContext& ctx);
std::unique_ptr<Integrator> make_ssr(const RenderContext& ctx);

const std::vector<IntegratorInfo>& integrator_registry() {
  static const std::vector<IntegratorInfo> registry = {
      {"pt", "reference path tracer: NEE + MIS, Russian roulette (path.*)", &make_path_tracer},
      {"restir-di", "ReSTIR DI, direct lighting with temporal and spatial reuse (di.*)", &make_restir_di},
      {"restir-gi", "ReSTIR GI, reuse of secondary hits with cached radiance, reconnection shift (gi.*)", &make_restir_gi},
      {"restir-pt", "ReSTIR PT, path reuse with reconnection / random replay / hybrid shifts (pt.*)", &make_restir_pt},
      {"ssr", "screen-space reflections: direct light plus reflections marched in the depth buffer (ssr.*); biased by design", &make_ssr},
  };
  return registry;
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

std::unique_ptr<Integrator> make_integrator(const std::string& name, const RenderContext& ctx) {
  return find_integrator(name).make(ctx);
}

}  // namespace rl
