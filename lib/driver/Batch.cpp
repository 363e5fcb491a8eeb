//! @file Batch.cpp
//! @brief Programs compiled once and run on many machines on threads (isosim --sweep,
//!        --calibrate).
#include "driver/Batch.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "support/Text.h"

#include "support/File.h"

#include "driver/Settings.h"

namespace iso::driver {

std::string pathBeside(const std::string& file, const std::string& path) {
  const std::filesystem::path given(path);
  if (given.is_absolute()) return given.lexically_normal().generic_string();
  return (std::filesystem::path(file).parent_path() / given).lexically_normal().generic_string();
}

support::Expected<std::string> readBatchFile(const std::string& path, const char* what) {
  bool whole = false;
  auto text = support::readFilePrefix(path, kMaxSettingsBytes + 1, whole);
  if (!text) return support::Error{path, fmt::format("cannot open the {} file: {}", what, text.error().message)};
  if (text->size() > kMaxSettingsBytes)
    return support::Error{path, fmt::format("the {} file is larger than {} MiB", what, kMaxSettingsBytes >> 20)};
  if (!support::isValidUtf8(*text)) return support::Error{path, fmt::format("the {} file is not UTF-8 text", what)};
  return std::move(*text);
}

void parallelFor(size_t n, unsigned jobs, const std::function<void(size_t)>& fn) {
  std::atomic<size_t> next{0};
  std::exception_ptr failure;
  std::mutex failureMutex;
  auto worker = [&] {
    for (size_t i; (i = next.fetch_add(1)) < n;) {
      try {
        fn(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failureMutex);
        if (!failure) failure = std::current_exception();
        next = n;
      }
    }
  };
  const size_t threads = std::min<size_t>(std::max(1u, jobs), n);
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t)
    pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool)
    t.join();
  if (failure) std::rethrow_exception(failure);
}

int batchMachines(const std::vector<std::string>& paths, const CommonOptions& common, const std::string& machine,
                  std::vector<BatchProgram>& programs, std::vector<BatchMachine>& bases, Io& io) {
  for (const std::string& program : paths) {
    BatchProgram p;
    p.path = program;
    p.common = common;
    if (p.common.machinePath.empty()) p.common.machinePath = machine;
    if (!applySettings(p.common, program, p.settings, io)) return kExitUsage;
    const std::string key = p.common.machinePath + '\n' + p.common.dialect;
    auto known = std::find_if(bases.begin(), bases.end(), [&](const BatchMachine& b) { return b.key == key; });
    p.base = static_cast<size_t>(known - bases.begin());
    if (known == bases.end()) {
      auto m = loadMachine(p.common, io);
      if (!m) return kExitUsage;
      bases.push_back({key, std::move(*m)});
    }
    programs.push_back(std::move(p));
  }
  return kExitOk;
}

bool compilesAlike(const machine::Machine& a, const machine::Machine& b) {
  if (a.dialect != b.dialect || a.specialM != b.specialM || a.parameters != b.parameters ||
      a.axes.size() != b.axes.size())
    return false;
  for (size_t i = 0; i < a.axes.size(); ++i)
    if (a.axes[i].letter != b.axes[i].letter) return false;
  return true;
}

int loadBatchPrograms(std::vector<BatchProgram>& programs, const std::vector<BatchMachine>& bases,
                      const std::vector<OutputPath>& outputs, const std::vector<std::string>& inputs, Io& io) {
  auto checkInputs = [&](const std::vector<std::string>& read) {
    std::vector<std::string> all = read;
    all.insert(all.end(), inputs.begin(), inputs.end());
    return checkOutputs(io, "isosim", outputs, all);
  };
  if (int rc = checkInputs({}); rc != kExitOk) return rc;
  for (BatchProgram& p : programs)
    if (int rc = loadProgram(p.path, {}, p.common, p.settings, bases[p.base].m, io, checkInputs, p.img, p.entry,
                             p.compileError);
        rc != kExitOk && p.compileError.empty())
      return rc;
  return kExitOk;
}

BatchRun runBatchProgram(const BatchProgram& p, const machine::Machine& m, const SimulateOptions& ro) {
  BatchRun run;
  if (!p.img) {
    run.status = sim::Status::Error;
    run.message = p.compileError;
    return run;
  }
  const sim::SimResult res = sim::simulate(*p.img, m, simOptions(ro, p.entry), nullptr);
  if (res.setupError != sim::SetupError::None) {
    run.status = sim::Status::Error;
    run.message = fmt::format("{}: {}", p.path, res.setupMessage);
    return run;
  }
  const sim::Summary& s = res.summary;
  run.status = s.status;
  run.cycleTimeS = s.cycleTimeS;
  run.blocks = s.blocks;
  run.spindleOnS = s.spindleOnS;
  run.toolChanges = s.toolChanges;
  run.warnings = s.warnings.size();
  run.message = s.message;
  return run;
}

} // namespace iso::driver
