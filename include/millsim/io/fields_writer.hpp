#pragma once
// Particle fields in HDF5 (one file per snapshot under OUT/fields/) indexed by OUT/fields.xdmf,
// a temporal collection of Polyvertex grids that ParaView opens directly. Checkpoints are HDF5
// too: a generic bag of named arrays so the state layout can grow without changing the format.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace millsim::io {

struct FieldArray {
  std::string name;        // e.g. "velocity", "radius"
  int components = 1;      // 1 (scalar) or 3 (vector)
  std::vector<float> data;  // count * components values, particle-major
};

struct FieldFrame {
  double time = 0.0;
  std::int64_t step = 0;
  std::size_t count = 0;
  std::vector<float> position;  // count * 3
  std::vector<FieldArray> arrays;
};

class FieldsWriter {
 public:
  // Creates out_dir/fields/. Existing snapshots from an earlier run of a restart are kept and
  // listed in the XDMF when `append` is true.
  explicit FieldsWriter(std::filesystem::path out_dir, bool append = false);
  // Writes fields/frame_NNNNNN.h5 and rewrites fields.xdmf (via a temp file + rename, so a crash
  // never leaves a truncated index).
  void write(const FieldFrame& frame);
  std::size_t framesWritten() const { return m_frames.size(); }

 private:
  struct Entry {
    double time;
    std::string file;
    std::size_t count;
    std::vector<std::pair<std::string, int>> arrays;
  };
  void writeXdmf() const;
  void scanExisting();       // append: index the snapshots an earlier run left in fields/
  void removeStaleFrames();  // fresh run: old snapshots must not leak into a later restart
  void addEntry(Entry entry);
  std::filesystem::path m_out;
  std::vector<Entry> m_frames;
  std::size_t m_next_index = 0;  // next file number; never reuses one, even after superseding
};

struct CheckpointData {
  double time = 0.0;
  std::int64_t step = 0;
  std::map<std::string, double> scalars;
  std::map<std::string, std::vector<double>> reals;
  std::map<std::string, std::vector<std::int64_t>> ints;
};

// Atomic: written to path + ".tmp" then renamed, so the previous checkpoint survives a crash.
void writeCheckpoint(const std::filesystem::path& path, const CheckpointData& data);
// Throws core::InputError naming the file when it is missing or not a millsim checkpoint.
CheckpointData readCheckpoint(const std::filesystem::path& path);

// Whether the HDF5 library this build links was built thread-safe (H5is_library_threadsafe):
// several simulations writing fields or checkpoints from threads at once need it.
bool hdf5ThreadSafe();

}  // namespace millsim::io
