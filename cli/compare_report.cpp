#include "cli/compare_report.h"

#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/atomic_write.h"
#include "io/image_io.h"
#include "ssao/contact_sheet.h"

namespace exao::cli {
namespace {

std::string slug(const std::string& name) {
  std::string out;
  for (const char c : name) out += c == '+' ? std::string("-plus") : std::string(1, c);
  return out;
}

AoImage ao_image(const ssao::View& view, const std::vector<float>& ao) {
  AoImage image;
  image.width = view.width;
  image.height = view.height;
  image.ao = ao;
  image.coverage.resize(ao.size());
  for (std::size_t p = 0; p < ao.size(); ++p) image.coverage[p] = view.valid[p] ? 1.0f : 0.0f;
  return image;
}

Result<void> write_ao(const ssao::View& view, const std::vector<float>& ao, const std::filesystem::path& base) {
  const AoImage image = ao_image(view, ao);
  if (auto ok = write_exr(image, base.string() + ".exr"); !ok) return ok;
  return write_png(image, base.string() + ".png");
}

Result<void> write_rgb(const ssao::RgbImage& image, const std::string& path) {
  return write_png_bytes(image.rgb, image.width, image.height, 3, path);
}

std::string percent(double share) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * share);
  return text;
}

std::string fixed(double v, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

nlohmann::json stereo_json(const ssao::Inconsistency& e) {
  return nlohmann::json{{"mean", e.mean}, {"rmse", e.rmse}, {"within_255", e.within_255}, {"pixels", e.pixels}, {"share", e.share}};
}

// One method's row of compare.json.
nlohmann::json method_json(const ssao::MethodResult& m, const ssao::MethodComparison& c) {
  const AoError& s = c.error;
  nlohmann::json row{{"name", ssao::compare_method_name(m.method)}, {"label", ssao::method_label(m.method)},
                     {"mean_abs", s.mean_abs()}, {"bias", s.bias()}, {"rmse", s.rmse()}, {"within_255", s.within_255_share()},
                     {"within_16", s.within_16_share()}, {"seconds", m.seconds},
                     {"map_seconds", m.map_seconds}};
  if (m.method == ssao::Method::SdSvao || m.method == ssao::Method::RtSvao || m.method == ssao::Method::RtSvaoRays) {
    row["flagged_pixels"] = m.flagged;
  }
  if (ssao::is_stereo(m.method)) row["stereo_pass"] = {{"reprojected_pixels", m.reprojected}, {"hole_pixels", m.holes}, {"both_eyes", true}};
  if (m.fragments) row["fragments"] = m.fragments;
  if (c.against) {
    const AoError& d = c.against->error;
    row["against"] = {{"method", ssao::compare_method_name(c.against->reference)}, {"mean_abs", d.mean_abs()}, {"rmse", d.rmse()},
                      {"within_255", d.within_255_share()}, {"time_ratio", c.against->time_ratio}};
  }
  if (c.stereo) row["stereo"] = stereo_json(*c.stereo);
  return row;
}

nlohmann::json compare_json(const CompareCommandOptions& o, const ssao::Comparison& comparison, const ShadowRays& rays,
                            double stereo_ipd) {
  const ssao::ViewResult& main = comparison.main();
  nlohmann::json j;
  j["scene"] = o.scene.scene;
  j["width"] = main.view.width;
  j["height"] = main.view.height;
  j["pixels"] = main.view.receivers.receivers.size();
  j["radius"] = rays.radius;
  j["falloff"] = falloff_name(rays.pattern.falloff);
  j["samples"] = rays.count();
  j["key"] = o.key;
  j["parameters"] = {{"directions", o.directions}, {"steps", o.steps}, {"bias", o.bias}, {"angles", o.angles}, {"cosine", o.cosine},
                     {"thickness", o.thickness}, {"sd_samples", o.sd_samples}, {"sd_alpha", o.sd_alpha}, {"blur", o.blur}};
  j["gbuffer_seconds"] = main.gbuffer_seconds;
  j["abuffer_seconds"] = main.fragment_seconds;
  j["exact"] = {{"seconds", main.exact_seconds}};
  if (comparison.exact_stereo) j["exact"]["stereo"] = stereo_json(*comparison.exact_stereo);
  j["methods"] = nlohmann::json::array();
  for (std::size_t i = 0; i < main.methods.size(); ++i) j["methods"].push_back(method_json(main.methods[i], comparison.methods[i]));
  if (comparison.pairs) {
    j["stereo"] = {{"ipd", *o.stereo}, {"pixels_compared", comparison.pairs->left.size()}, {"left_pixels", comparison.pairs->left_visible}};
  }
  j["stereo_hbao_plus_ipd"] = stereo_ipd;
  j["other_eye_gbuffer_seconds"] = main.other_eye_seconds;
  if (main.secondary) {
    const Camera& c = *main.secondary;
    j["secondary_camera"] = {{"eye", {c.eye.x, c.eye.y, c.eye.z}}, {"forward", {c.forward.x, c.forward.y, c.forward.z}},
                             {"yfov_degrees", glm::degrees(c.yfov)}, {"angle_degrees", o.mv_angle}};
  }
  return j;
}

// A variant against the row it approximates, one line.
std::string variant_line(const ssao::MethodResult& m, const ssao::VariantError& against) {
  const AoError& d = against.error;
  return std::string(ssao::method_label(m.method)) + ": " +
         (m.fragments ? std::to_string(m.fragments) + " fragments, " : std::string()) + "mean |AO - " +
         ssao::method_label(against.reference) + "| " + fixed(d.mean_abs(), 5) + ", RMSE " + fixed(d.rmse(), 5) + ", " +
         percent(d.within_255_share()) + " within 1/255, time " + fixed(m.seconds, 3) + " s (" + fixed(against.time_ratio, 2) + "x)";
}

}  // namespace

Result<void> write_compare_pictures(const ssao::Comparison& comparison, const ShadowRays& rays,
                                    const std::filesystem::path& dir) {
  const ssao::ViewResult& main = comparison.main();
  if (auto ok = write_ao(main.view, main.exact, dir / "exact"); !ok) return ok;
  std::vector<ssao::RgbImage> greys, heats;
  greys.reserve(main.methods.size() + 1);
  heats.reserve(main.methods.size());
  greys.push_back(ssao::grey_image(main.exact, main.view.valid, main.view.width, main.view.height));
  for (const ssao::MethodResult& m : main.methods) {
    const std::string name = slug(ssao::compare_method_name(m.method));
    if (auto ok = write_ao(main.view, m.ao, dir / name); !ok) return ok;
    heats.push_back(ssao::heat_map(m.ao, main.exact, main.view.valid, main.view.width, main.view.height));
    if (auto ok = write_rgb(heats.back(), (dir / (name + "-error.png")).string()); !ok) return ok;
    greys.push_back(ssao::grey_image(m.ao, main.view.valid, main.view.width, main.view.height));
  }
  std::vector<ssao::SheetCell> cells;
  const ssao::RgbImage legend = ssao::heat_map_legend(main.view.width, main.view.height);
  cells.push_back({"EXACT N=" + std::to_string(rays.count()), &greys[0], &legend});
  for (std::size_t i = 0; i < main.methods.size(); ++i) {
    // Label and mean abs error: at most 20 characters fit over a 240-pixel tile.
    cells.push_back({std::string(ssao::method_label(main.methods[i].method)) + " " +
                         fixed(comparison.methods[i].error.mean_abs(), 3),
                     &greys[i + 1], &heats[i]});
  }
  return write_rgb(ssao::contact_sheet(cells, 4, 320), (dir / "contact-sheet.png").string());
}

std::string compare_table(const ssao::Comparison& comparison, const ShadowRays& rays) {
  const ssao::ViewResult& main = comparison.main();
  const bool stereo = comparison.pairs.has_value();
  std::ostringstream md;
  md << "| method | mean abs error | bias | RMSE | within 1/255 | within 1/16 | time (s) |" << (stereo ? " stereo E |" : "") << "\n";
  md << "|---|---|---|---|---|---|---|" << (stereo ? "---|" : "") << "\n";
  md << "| exact (bvh, N = " << rays.count() << ") | 0 | 0 | 0 | 100% | 100% | " << fixed(main.exact_seconds, 3) << " |"
     << (stereo ? " " + fixed(comparison.exact_stereo->mean, 4) + " |" : "") << "\n";
  for (std::size_t i = 0; i < main.methods.size(); ++i) {
    const ssao::MethodResult& m = main.methods[i];
    const AoError& s = comparison.methods[i].error;
    const std::optional<ssao::Inconsistency>& e = comparison.methods[i].stereo;
    md << "| " << ssao::method_label(m.method) << " | " << fixed(s.mean_abs(), 4) << " | " << (s.bias() >= 0 ? "+" : "") << fixed(s.bias(), 4)
       << " | " << fixed(s.rmse(), 4) << " | " << percent(s.within_255_share()) << " | " << percent(s.within_16_share()) << " | " << fixed(m.seconds, 3) << " |"
       << (e ? " " + fixed(e->mean, 4) + " |" : "") << "\n";
  }
  return md.str();
}

Result<void> write_compare_report(const CompareCommandOptions& flags, const ssao::Comparison& comparison,
                                  const ShadowRays& rays, double stereo_ipd, const std::filesystem::path& dir) {
  const nlohmann::json j = compare_json(flags, comparison, rays, stereo_ipd);
  if (auto ok = write_file_atomically((dir / "compare.json").string(), j.dump(2) + "\n"); !ok) return ok;
  return write_file_atomically((dir / "compare.md").string(), compare_table(comparison, rays));
}

void print_compare_summary(const CompareCommandOptions& o, const ssao::Comparison& comparison, const Scene& scene,
                           const ShadowRays& rays, double stereo_ipd) {
  const ssao::ViewResult& main = comparison.main();
  std::printf("%s: %zu triangles, %dx%d, %zu pixels, r=%g, N=%d, G-buffer %.3f s, A-buffer %.3f s -> %s/\n",
              o.scene.scene.c_str(), scene.triangle_count(), main.view.width, main.view.height,
              main.view.receivers.receivers.size(), static_cast<double>(rays.radius), rays.count(), main.gbuffer_seconds,
              main.fragment_seconds, o.output.c_str());
  std::printf("%s", compare_table(comparison, rays).c_str());
  for (std::size_t i = 0; i < main.methods.size(); ++i) {
    if (comparison.methods[i].against) std::printf("%s\n", variant_line(main.methods[i], *comparison.methods[i].against).c_str());
  }
  if (main.secondary) {
    const Camera& c = *main.secondary;
    std::printf("MV-SD-HBAO+: secondary eye (%g, %g, %g), turned %g degrees, field of view %.1f degrees\n", static_cast<double>(c.eye.x),
                static_cast<double>(c.eye.y), static_cast<double>(c.eye.z), o.mv_angle, static_cast<double>(glm::degrees(c.yfov)));
  }
  for (const ssao::MethodResult& m : main.methods) {
    if (!ssao::is_stereo(m.method)) continue;
    std::printf("%s: other eye %g to the side, %zu pixels reprojected, %zu holes evaluated (both eyes timed)\n", ssao::method_label(m.method),
                stereo_ipd, m.reprojected, m.holes);
    break;
  }
  if (comparison.pairs) {
    std::printf("stereo: IPD %g, %zu of %zu left pixels seen by both eyes; E = mean |AO_left - AO_right reprojected|, key %s\n",
                *o.stereo, comparison.pairs->left.size(), comparison.pairs->left_visible, o.key.c_str());
  }
}

}  // namespace exao::cli
