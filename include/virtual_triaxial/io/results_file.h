// Results file (DESIGN §7): one HDF5 group per test holding the time series
// of dem::Measures and the test summary.
//
// Layout (root attrs format "virtual_triaxial results", format_version 1):
//   /<group>/series/<channel>   one dataset per channel, N rows, with `units`:
//     time [s], step [1] (int64), stress (N,9) row-major [Pa], p, q [Pa],
//     phi [rad], principal_stress (N,3) [Pa], strain (N,3) [1],
//     volumetric_strain [1], volume [m^3], void_ratio [1], ufr, iuf,
//     moment_index, inertia_index [1], coordination_number,
//     raw_coordination_number, idle_mass_fraction [1], contacts,
//     sliding_contacts [1] (int64), max_overlap_ratio [1],
//     energy_boundary_work, energy_damping, energy_friction,
//     energy_kinetic_translational, energy_kinetic_rotational, energy_elastic,
//     energy_balance_error (derived), energy_kinetic_reference,
//     energy_elastic_reference [J], energy_has_reference [1] (uint8)
//   /<group>/summary            numbers as float64 attributes, texts as
//                               string attributes
// Sign conventions are those of dem::Measures (compression positive).
//
// ResultsWriter keeps the series in memory and rewrites the whole file on
// every flush() through a temporary file and rename, so the file on disk is
// always complete. Other top-level groups already in the file (other tests)
// are copied over unchanged; this writer's group is replaced. One writer per
// file at a time (two concurrent writers would lose each other's updates).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "virtual_triaxial/dem/measures.h"

namespace vt::io {

inline constexpr const char* kResultsFormat = "virtual_triaxial results";
inline constexpr std::int64_t kResultsFormatVersion = 1;

class ResultsWriter {
 public:
  /// Throws if `group` is not a valid group name, or if `path` exists and is
  /// not a results file (it is never overwritten then). Nothing is written
  /// before the first flush().
  explicit ResultsWriter(const std::string& path, const std::string& group = "test");
  /// Flushes (errors swallowed) unless close() was called.
  ~ResultsWriter();
  ResultsWriter(const ResultsWriter&) = delete;
  ResultsWriter& operator=(const ResultsWriter&) = delete;

  void append(const dem::Measures& m);
  /// Replaces the series in memory (a resumed run: the rows up to its
  /// checkpoint, read back with read_results_series()).
  void restore_series(std::vector<dem::Measures> rows);
  /// Replaces the summary. A key may not be both a number and a text.
  void set_summary(const std::map<std::string, double>& numbers,
                   const std::map<std::string, std::string>& texts);
  /// Write everything atomically; throws std::runtime_error naming the path.
  void flush();
  /// flush() and refuse further appends.
  void close();

  const std::string& path() const { return path_; }
  const std::string& group() const { return group_; }
  std::size_t size() const { return series_.size(); }

 private:
  void check_open(const char* what) const;

  std::string path_, group_;
  std::vector<dem::Measures> series_;
  std::map<std::string, double> numbers_;
  std::map<std::string, std::string> texts_;
  bool closed_ = false;
};

/// The series of one test group (all dem::Measures fields restored).
std::vector<dem::Measures> read_results_series(const std::string& path, const std::string& group = "test");
/// Numeric summary attributes of /<group>/summary.
std::map<std::string, double> read_summary_numbers(const std::string& path, const std::string& group = "test");
/// Text summary attributes of /<group>/summary.
std::map<std::string, std::string> read_summary_texts(const std::string& path, const std::string& group = "test");

}  // namespace vt::io
