#pragma once
// Full runs ("Make"): one at a time on a thread of their own, with their progress for the page's bar
// and their files in a folder of the work folder that only they write.

#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "run_request.hpp"

namespace studio {

enum class JobState { queued, running, done, failed, cancelled };
const char* to_string(JobState state);

struct JobStatus {
  JobState state = JobState::queued;
  double fraction = 0.0;  // of the whole job, 0..1
  double eta = -1.0;      // seconds left; negative while unknown
  std::string stage, error;
  std::string error_option;        // failed on an option: its name
  std::vector<std::string> files;  // when done: the names GET .../files/NAME serves
  std::string report;              // when done: the report's JSON text, hole table included
  long version = 0;                // counts changes, for the event stream
  bool finished() const {
    return state == JobState::done || state == JobState::failed || state == JobState::cancelled;
  }
};

class Job {
 public:
  Job(int id, std::filesystem::path folder) : id_(id), folder_(std::move(folder)) {}
  int id() const { return id_; }
  const std::filesystem::path& folder() const { return folder_; }
  JobStatus status() const;
  // Waits until the status changes from `version` or `seconds` pass; returns the status then.
  JobStatus wait_change(long version, double seconds) const;
  void cancel() { cancel_ = true; }

 private:
  friend class Jobs;
  void update(const std::function<void(JobStatus&)>& change);
  const int id_;
  const std::filesystem::path folder_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  JobStatus status_;
  std::atomic<bool> cancel_{false};
};

// A second job while one runs.
class Busy : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Jobs {
 public:
  explicit Jobs(std::filesystem::path folder) : folder_(std::move(folder)) {}
  ~Jobs() { shutdown(); }
  Jobs(const Jobs&) = delete;
  Jobs& operator=(const Jobs&) = delete;
  // Starts the job; throws Busy while another runs.
  std::shared_ptr<Job> start(RunRequest request);
  std::shared_ptr<Job> get(int id) const;
  // Cancels the running job and waits for it: its files are removed. Later starts are refused.
  void shutdown();

 private:
  void run(const std::shared_ptr<Job>& job, const RunRequest& request);
  std::filesystem::path folder_;
  mutable std::mutex mutex_;
  std::map<int, std::shared_ptr<Job>> jobs_;
  std::shared_ptr<Job> running_;
  std::thread worker_;
  int next_id_ = 1;
  bool stopped_ = false;
};

// The files a job writes, in the order the API lists them.
inline const std::vector<std::string> kJobFiles{"part.3mf", "part.stl", "report.json", "holes.csv"};

}  // namespace studio
