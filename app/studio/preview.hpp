#pragma once
// Previews: the pattern alone (Options::preview), a second or so; a newer preview cancels the one still
// running, so that the page always shows the latest edit.

#include <atomic>
#include <memory>
#include <mutex>

#include <nlohmann/json.hpp>

#include "run_request.hpp"

namespace studio {

class Previews {
 public:
  // The preview's answer: holes (count), centres, diameters, figures and the painted surface (base64
  // arrays). Throws poreshell::Error: cancelled when a newer preview (or the shutdown) took over.
  nlohmann::json run(const RunRequest& request);
  // Cancels the preview running, if any, and every later one (shutdown).
  void stop();

 private:
  std::mutex mutex_;
  std::shared_ptr<std::atomic<bool>> current_;
  bool stopped_ = false;
};

// The figures the page's panel shows, from a preview's output and report (lengths mm, mass g at PLA's
// 1.24 g/cm^3 over the wall left after the holes).
nlohmann::json preview_figures(const poreshell::Result& result);

// A model's surface for the page (its brush and picking): float32 positions in mm (unit applied, before
// Options::scale) and uint32 indices, base64; a point cloud's points alone.
nlohmann::json model_mesh_json(const Model& model);

}  // namespace studio
