#include "jobs.hpp"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>
#include <system_error>

namespace studio {

namespace fs = std::filesystem;

const char* to_string(JobState state) {
  switch (state) {
    case JobState::queued:
      return "queued";
    case JobState::running:
      return "running";
    case JobState::done:
      return "done";
    case JobState::failed:
      return "failed";
    case JobState::cancelled:
      return "cancelled";
  }
  return "failed";
}

namespace {

// The share of a run's time each stage takes (the bunny and the sleeve at 8 mm, 2 cores): the bar moves
// evenly enough without a per-model fit.
double overall_fraction(std::string_view stage, double fraction) {
  static constexpr std::pair<std::string_view, double> kStages[] = {
      {"input", 0.04}, {"band", 0.04}, {"solve", 0.52}, {"shell", 0.2}, {"mesh", 0.12}, {"holes", 0.04}};
  double before = 0.0;
  for (const auto& [name, share] : kStages) {
    if (name == stage) return std::clamp(before + share * fraction, 0.0, 1.0) * 0.96;  // the rest: writing
    before += share;
  }
  return 0.0;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

JobStatus Job::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

JobStatus Job::wait_change(long version, double seconds) const {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return status_.version != version; });
  return status_;
}

void Job::update(const std::function<void(JobStatus&)>& change) {
  {
    std::lock_guard lock(mutex_);
    change(status_);
    ++status_.version;
  }
  changed_.notify_all();
}

std::shared_ptr<Job> Jobs::start(RunRequest request) {
  std::lock_guard lock(mutex_);
  if (stopped_) throw Busy("the studio is stopping");
  if (running_ && !running_->status().finished())
    throw Busy("job " + std::to_string(running_->id()) + " is still running: cancel it or wait for it");
  if (worker_.joinable()) worker_.join();  // finished: its thread is ending
  const int id = next_id_++;
  auto job = std::make_shared<Job>(id, folder_ / std::to_string(id));
  jobs_[id] = job;
  running_ = job;
  worker_ = std::thread([this, job, request = std::move(request)] { run(job, request); });
  return job;
}

std::shared_ptr<Job> Jobs::get(int id) const {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  return it == jobs_.end() ? nullptr : it->second;
}

void Jobs::shutdown() {
  std::thread worker;
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
    if (running_) running_->cancel();
    worker = std::move(worker_);
  }
  if (worker.joinable()) worker.join();
}

void Jobs::run(const std::shared_ptr<Job>& job, const RunRequest& request) {
  // A run's free memory goes back to the system when it ends: the studio then idles at its models'
  // size (100 MB resident after the sleeve's Make without it, 30 with it).
  struct Trim {
    ~Trim() { ::malloc_trim(0); }
  } trim;
  const auto start = std::chrono::steady_clock::now();
  job->update([](JobStatus& s) { s.state = JobState::running; });
  try {
    poreshell::Options options = request.options;
    options.preview = false;
    const poreshell::Input input = masked_input(request.model->input, request.mask, options);
    poreshell::RunControl control;
    control.cancel = &job->cancel_;
    control.progress = [&](const poreshell::Progress& p) {
      const double f = overall_fraction(p.stage, p.fraction);
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      job->update([&](JobStatus& s) {
        s.stage = std::string(p.stage);
        s.fraction = std::max(s.fraction, f);
        s.eta = s.fraction > 0.03 ? elapsed * (1.0 - s.fraction) / s.fraction : -1.0;
      });
    };
    poreshell::Result result = poreshell::perforate(input, options, control);
    fs::create_directories(job->folder());
    const auto check_cancel = [&] {
      if (job->cancel_) throw poreshell::Error(poreshell::ErrorCode::cancelled, "the job was cancelled");
    };
    // The same calls as the command line's, so that a project run there writes the same bytes.
    check_cancel();
    poreshell::save_mesh(job->folder() / "part.3mf", result.outputs.front());
    result.report.outputs.front().path = "part.3mf";
    check_cancel();
    poreshell::save_mesh(job->folder() / "part.stl", result.outputs.front());
    check_cancel();
    poreshell::save_report(job->folder() / "report.json", result.report, result.outputs);
    poreshell::save_holes_csv(job->folder() / "holes.csv", result.outputs.front().holes);
    std::string report = read_text(job->folder() / "report.json");
    job->update([&](JobStatus& s) {
      s.state = JobState::done;
      s.fraction = 1.0;
      s.eta = 0.0;
      s.files = kJobFiles;
      s.report = std::move(report);
    });
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove_all(job->folder(), ignored);  // no partial files
    const auto* error = dynamic_cast<const poreshell::Error*>(&e);
    const bool cancelled = job->cancel_ || (error && error->code() == poreshell::ErrorCode::cancelled);
    job->update([&](JobStatus& s) {
      s.state = cancelled ? JobState::cancelled : JobState::failed;
      s.error = e.what();
      if (error) s.error_option = error->option();
      s.eta = 0.0;
    });
  }
}

}  // namespace studio
