// Sampled studies over MPI ranks (built when CMake finds MPI: VIADUCT_HAVE_MPI). Rank 0 runs a
// coordinator thread that hands out units of samples to whichever rank asks (dynamic load
// balancing: cases differ in cost), gathers the results and passes them to the sink in sample
// order; every rank (rank 0's main thread too, when MPI_THREAD_MULTIPLE is given) computes.
#include "viaduct/study/sampled.hpp"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <exception>
#include <map>
#include <thread>

#include "viaduct/core/error.hpp"

#ifdef VIADUCT_HAVE_MPI
#include <mpi.h>
#endif

namespace viaduct::study {

namespace sampled_mpi_detail {

MpiWorld& world() {
  static MpiWorld w;
  return w;
}
bool& initialised() {
  static bool b = false;
  return b;
}

// Started by mpirun (Open MPI) or a PMI launcher (srun, MPICH's hydra)?
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

// SampleBatch <-> bytes (same machine and build on every rank: native layout).
struct Writer {
  std::vector<char> bytes;
  template <class T>
  void put(const T& x) {
    const char* p = reinterpret_cast<const char*>(&x);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void put(const std::string& s) {
    put(std::uint64_t(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  void put(bool b) { put(char(b)); }
  template <class... T>
  void operator()(const T&... x) {
    (put(x), ...);
  }
};
struct Reader {
  const std::vector<char>& bytes;
  std::size_t at = 0;
  template <class T>
  void get(T& x) {
    if (at + sizeof(T) > bytes.size()) throw std::logic_error("MPI result message cut short");
    std::memcpy(&x, bytes.data() + at, sizeof(T));
    at += sizeof(T);
  }
  void get(std::string& s) {
    std::uint64_t n = 0;
    get(n);
    if (at + n > bytes.size()) throw std::logic_error("MPI result message cut short");
    s.assign(bytes.data() + at, n);
    at += n;
  }
  void get(bool& b) {
    char c = 0;
    get(c);
    b = c != 0;
  }
  template <class... T>
  void operator()(T&... x) {
    (get(x), ...);
  }
};

// The fields sent, in their order: one list each for pack and unpack (Io: Writer or Reader).
template <class Io, class Batch>
void header_fields(Io& io, Batch& b) {
  io(b.begin, b.end, b.n_cases, b.n_steps);
}
template <class Io, class Peak>
void peak_fields(Io& io, Peak& p) {
  io(p.sample, p.train, p.station, p.speed, p.max_abs_acc, p.max_abs_disp);
}
template <class Io, class Failure>
void failure_fields(Io& io, Failure& f) {
  io(f.sample, f.train, f.speed, f.message, f.input_error);
}

std::vector<char> pack(const SampleBatch& b) {
  Writer w;
  header_fields(w, b);
  w.put(std::uint64_t(b.peaks.size()));
  for (const auto& p : b.peaks) peak_fields(w, p);
  w.put(std::uint64_t(b.failures.size()));
  for (const auto& f : b.failures) failure_fields(w, f);
  return w.bytes;
}

SampleBatch unpack(const std::vector<char>& bytes) {
  Reader r{bytes};
  SampleBatch b;
  header_fields(r, b);
  std::uint64_t n = 0;
  r.get(n);
  b.peaks.resize(n);
  for (auto& p : b.peaks) peak_fields(r, p);
  r.get(n);
  b.failures.resize(n);
  for (auto& f : b.failures) failure_fields(r, f);
  return b;
}

}  // namespace sampled_mpi_detail

MpiWorld mpi_world() { return sampled_mpi_detail::world(); }

#ifndef VIADUCT_HAVE_MPI

// Started by mpirun on several ranks, this build would run the whole study on every one of them
// into the same files: say so instead (main refuses to run).
MpiWorld mpi_start(int*, char***) {
  MpiWorld& w = sampled_mpi_detail::world();
  for (const char* size : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(size)) w.size = std::max(1, std::atoi(v));
  for (const char* rank : {"OMPI_COMM_WORLD_RANK", "PMI_RANK"})
    if (const char* v = std::getenv(rank)) w.rank = std::atoi(v);
  w.without_mpi = w.size > 1;
  return w;
}
void mpi_finish() {}
Index mpi_broadcast(Index value) { return value; }
SampledRunSummary run_samples_mpi(Index begin, Index end, const VariantMaker& make, const BatchSink& sink,
                                  const SampledRunOptions& options) {
  return run_samples(begin, end, make, sink, options);
}

#else

namespace sampled_mpi_detail {

enum Tag { kRequest = 101, kAssign = 102, kResult = 103 };

// Rank 0's coordinator: units out on request, results in, the sink fed in sample order.
SampledRunSummary coordinate(Index begin, Index end, Index unit, int size, const BatchSink& sink, const ProgressSink& progress) {
  SampledRunSummary sum;
  Index next = begin, flushed = begin;
  int stopped = 0;
  std::map<Index, SampleBatch> pending;
  while (stopped < size || flushed < end) {
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, kRequest, MPI_COMM_WORLD, &flag, &st);
    if (flag) {
      long long dummy = 0;
      MPI_Recv(&dummy, 1, MPI_LONG_LONG, st.MPI_SOURCE, kRequest, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      long long range[2] = {-1, -1};
      if (next < end) {
        range[0] = next;
        range[1] = std::min(end, next + unit);
        next = range[1];
      } else {
        ++stopped;
      }
      MPI_Send(range, 2, MPI_LONG_LONG, st.MPI_SOURCE, kAssign, MPI_COMM_WORLD);
      continue;
    }
    MPI_Iprobe(MPI_ANY_SOURCE, kResult, MPI_COMM_WORLD, &flag, &st);
    if (flag) {
      int count = 0;
      MPI_Get_count(&st, MPI_CHAR, &count);
      std::vector<char> bytes(static_cast<std::size_t>(count));
      MPI_Recv(bytes.data(), count, MPI_CHAR, st.MPI_SOURCE, kResult, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      SampleBatch b = unpack(bytes);
      sum.n_samples += b.end - b.begin;
      sum.n_cases += b.n_cases;
      sum.n_failed += Index(b.failures.size());
      sum.n_steps_total += b.n_steps;
      pending.emplace(b.begin, std::move(b));
      for (auto it = pending.find(flushed); it != pending.end(); it = pending.find(flushed)) {
        sink(it->second);
        flushed = it->second.end;
        pending.erase(it);
        if (progress) progress(std::size_t(flushed - begin), std::size_t(end - begin));
      }
      continue;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));  // Open MPI's blocking calls would spin a core
  }
  return sum;
}

// Any rank: ask for a unit, compute it, send its results; until told to stop.
SampledRunSummary work(const VariantMaker& make, const SampledRunOptions& options) {
  SampledRunSummary mine;
  SampledRunOptions o = options;
  o.progress = nullptr;
  while (true) {
    long long ask = 0, range[2] = {-1, -1};
    MPI_Send(&ask, 1, MPI_LONG_LONG, 0, kRequest, MPI_COMM_WORLD);
    MPI_Recv(range, 2, MPI_LONG_LONG, 0, kAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (range[0] < 0) break;
    o.batch = Index(range[1] - range[0]);
    SampleBatch got;
    const SampledRunSummary s = run_samples(Index(range[0]), Index(range[1]), make, [&](const SampleBatch& b) { got = b; }, o);
    mine.n_samples += s.n_samples;
    mine.n_cases += s.n_cases;
    mine.n_failed += s.n_failed;
    mine.n_steps_total += s.n_steps_total;
    const std::vector<char> bytes = pack(got);
    MPI_Send(bytes.data(), int(bytes.size()), MPI_CHAR, 0, kResult, MPI_COMM_WORLD);
  }
  return mine;
}

}  // namespace sampled_mpi_detail

MpiWorld mpi_start(int* argc, char*** argv) {
  using namespace sampled_mpi_detail;
  if (!launched_by_mpi()) return world();
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_MULTIPLE, &provided);
  initialised() = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &world().rank);
  MPI_Comm_size(MPI_COMM_WORLD, &world().size);
  world().threads_multiple = provided >= MPI_THREAD_MULTIPLE;
  return world();
}

void mpi_finish() {
  if (sampled_mpi_detail::initialised()) MPI_Finalize();
  sampled_mpi_detail::initialised() = false;
}

Index mpi_broadcast(Index value) {
  if (!sampled_mpi_detail::initialised()) return value;
  long long v = value;
  MPI_Bcast(&v, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  return Index(v);
}

SampledRunSummary run_samples_mpi(Index begin, Index end, const VariantMaker& make, const BatchSink& sink,
                                  const SampledRunOptions& options) {
  using namespace sampled_mpi_detail;
  const MpiWorld w = world();
  if (!initialised() || w.size < 2) return run_samples(begin, end, make, sink, options);
  if (options.batch < 1 || begin < 0 || end < begin)
    throw InputError("SampledRunOptions: violated constraint batch >= 1, 0 <= begin <= end");
  if (w.rank != 0) return work(make, options);
  const auto t0 = std::chrono::steady_clock::now();
  // Without MPI_THREAD_MULTIPLE rank 0 only coordinates (the others compute).
  const int workers = w.threads_multiple ? w.size : w.size - 1;
  SampledRunSummary sum;
  std::exception_ptr failed;
  std::thread coordinator([&] {
    try {
      sum = coordinate(begin, end, options.batch, workers, sink, options.progress);
    } catch (...) {
      failed = std::current_exception();
    }
    if (failed) MPI_Abort(MPI_COMM_WORLD, 1);  // the sink could not write: no rank can go on
  });
  if (w.threads_multiple) work(make, options);
  coordinator.join();
  if (failed) std::rethrow_exception(failed);
  sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

#endif

}  // namespace viaduct::study
