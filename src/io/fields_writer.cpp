// Particle snapshots and checkpoints on the HDF5 C API.
//
// Files:
//   OUT/fields/frame_NNNNNN.h5  one per snapshot: /position (count x 3 float32), one float32
//                               dataset per FieldArray (count x components; count for scalars),
//                               root attributes time (float64) and step (int64).
//   OUT/fields.xdmf             XDMF 3 Temporal collection of Uniform Polyvertex grids whose
//                               DataItems name the frames by relative path, so the output folder
//                               can be moved as a whole and ParaView still finds the data.
//   checkpoint (any path)       root attributes time, step and millsim_checkpoint = 1 (format
//                               version); /scalars (one float64 attribute each), /reals/<name>
//                               (1-D float64), /ints/<name> (1-D int64).
// Every file is written under a temporary name and renamed into place, so a crash leaves the old
// version or the new one, never a truncated file that a restart would then trip over.
//
// A restart resumes from a checkpoint that is usually older than the last snapshot, so the
// snapshots it writes repeat times already on disk. Newer files supersede older index entries at
// the same or later time (see addEntry); the old files stay on disk but leave the index, which
// keeps the temporal collection strictly increasing as ParaView requires.
#include "millsim/io/fields_writer.hpp"

#include <hdf5.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "millsim/core/error.hpp"

namespace millsim::io {

namespace fs = std::filesystem;

namespace {

constexpr int kCheckpointFormat = 1;
constexpr const char* kFramePrefix = "frame_";
constexpr const char* kFrameSuffix = ".h5";

// ---- HDF5 plumbing ------------------------------------------------------------------------------

// Owns one HDF5 identifier; close() exists so writers can see a failed flush before renaming.
class Hid {
 public:
  using Closer = herr_t (*)(hid_t);
  Hid(hid_t id, Closer closer) : m_id(id), m_closer(closer) {}
  Hid(const Hid&) = delete;
  Hid& operator=(const Hid&) = delete;
  ~Hid() { close(); }
  hid_t get() const { return m_id; }
  herr_t close() {
    const herr_t status = m_id >= 0 ? m_closer(m_id) : 0;
    m_id = -1;
    return status;
  }

 private:
  hid_t m_id;
  Closer m_closer;
};

// HDF5 prints its whole error stack to stderr by default; probing a file the user named (is it
// HDF5? has it the marker?) must fail quietly and leave the message to our exception.
class QuietHdf5Errors {
 public:
  QuietHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &m_func, &m_data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;
  ~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, m_func, m_data); }

 private:
  H5E_auto2_t m_func = nullptr;
  void* m_data = nullptr;
};

// Which exception a failure becomes: our own output failing is an environment problem
// (runtime_error); a file the user pointed us at being wrong is an input problem (InputError,
// which the CLI reports as one line and exit code 2).
enum class Blame { Output, Input };

struct Where {
  std::string path;
  Blame blame;
};

[[noreturn]] void fail(const Where& where, const std::string& what) {
  const std::string message = where.path + ": " + what;
  if (where.blame == Blame::Input) throw core::InputError(message);
  throw std::runtime_error(message);
}

// HDF5 reports failure as a negative hid_t / herr_t / htri_t.
template <class T>
T need(T result, const Where& where, const std::string& what) {
  if (result < 0) fail(where, what);
  return result;
}

Hid createGroup(hid_t loc, const char* name, const Where& where) {
  return Hid(need(H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), where,
                  std::string("cannot create group /") + name),
             H5Gclose);
}

Hid openGroup(hid_t loc, const char* name, const Where& where) {
  return Hid(need(H5Gopen2(loc, name, H5P_DEFAULT), where, std::string("missing group /") + name), H5Gclose);
}

void writeAttribute(hid_t loc, const char* name, hid_t file_type, hid_t mem_type, const void* value,
                    const Where& where) {
  const std::string what = std::string("cannot write attribute ") + name;
  Hid space(need(H5Screate(H5S_SCALAR), where, what), H5Sclose);
  Hid attr(need(H5Acreate2(loc, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), where, what), H5Aclose);
  need(H5Awrite(attr.get(), mem_type, value), where, what);
}

template <class T>
T readAttribute(hid_t loc, const char* name, hid_t mem_type, const Where& where) {
  const std::string what = std::string("cannot read attribute ") + name;
  Hid attr(need(H5Aopen(loc, name, H5P_DEFAULT), where, "missing attribute " + std::string(name)), H5Aclose);
  Hid space(need(H5Aget_space(attr.get()), where, what), H5Sclose);
  // H5Aread fills as many values as the attribute holds; anything but one would overrun `value`.
  if (H5Sget_simple_extent_npoints(space.get()) != 1)
    fail(where, "attribute " + std::string(name) + " is not a scalar");
  T value{};
  need(H5Aread(attr.get(), mem_type, &value), where, what);
  return value;
}

// rank 1 or 2; an empty array still gets its (zero-extent) dataset so readers see the name.
void writeDataset(hid_t loc, const std::string& name, const void* data, int rank, const hsize_t* dims,
                  hid_t file_type, hid_t mem_type, const Where& where) {
  const std::string what = "cannot write dataset " + name;
  Hid space(need(H5Screate_simple(rank, dims, nullptr), where, what), H5Sclose);
  Hid set(need(H5Dcreate2(loc, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), where,
               what),
          H5Dclose);
  // H5Dwrite rejects a null buffer even for zero elements, and an empty vector's data() may be null.
  if (H5Sget_simple_extent_npoints(space.get()) > 0)
    need(H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), where, what);
}

std::vector<hsize_t> datasetDims(hid_t loc, const std::string& name, const Where& where) {
  Hid set(need(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), where, "missing dataset " + name), H5Dclose);
  Hid space(need(H5Dget_space(set.get()), where, "cannot read shape of " + name), H5Sclose);
  const int rank = need(H5Sget_simple_extent_ndims(space.get()), where, "cannot read shape of " + name);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  need(H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr), where, "cannot read shape of " + name);
  return dims;
}

template <class T>
std::vector<T> readVector(hid_t loc, const std::string& name, hid_t mem_type, const Where& where) {
  const std::vector<hsize_t> dims = datasetDims(loc, name, where);
  if (dims.size() != 1) fail(where, "dataset " + name + " is not one-dimensional");
  std::vector<T> values(static_cast<std::size_t>(dims[0]));
  if (values.empty()) return values;
  Hid set(need(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), where, "missing dataset " + name), H5Dclose);
  need(H5Dread(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), where,
       "cannot read dataset " + name);
  return values;
}

herr_t collectLinkName(hid_t, const char* name, const H5L_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

herr_t collectAttributeName(hid_t, const char* name, const H5A_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

// Creation order when the file tracks it (our frames do, so a restart lists the arrays in the
// order they were written); name order otherwise.
std::vector<std::string> linkNames(hid_t group, const Where& where) {
  std::vector<std::string> names;
  hsize_t index = 0;
  if (H5Literate(group, H5_INDEX_CRT_ORDER, H5_ITER_INC, &index, collectLinkName, &names) >= 0) return names;
  names.clear();
  index = 0;
  need(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, &index, collectLinkName, &names), where, "cannot list group");
  return names;
}

std::vector<std::string> attributeNames(hid_t loc, const Where& where) {
  std::vector<std::string> names;
  hsize_t index = 0;
  need(H5Aiterate2(loc, H5_INDEX_NAME, H5_ITER_INC, &index, collectAttributeName, &names), where,
       "cannot list attributes");
  return names;
}

bool isHdf5(const fs::path& path) {
#if H5_VERSION_GE(1, 12, 0)
  return H5Fis_accessible(path.c_str(), H5P_DEFAULT) > 0;
#else
  return H5Fis_hdf5(path.c_str()) > 0;
#endif
}

void renameInto(const fs::path& from, const fs::path& to) {
  std::error_code error;
  fs::rename(from, to, error);
  if (error)
    throw std::runtime_error(to.string() + ": cannot move " + from.string() + " into place: " + error.message());
}

fs::path tempPathFor(const fs::path& path) { return fs::path(path.string() + ".tmp"); }

// HDF5 would silently create nested groups for "a/b"; "." and "" are not valid link names.
void requireLinkName(const std::string& name, const char* what) {
  if (name.empty() || name == "." || name.find('/') != std::string::npos)
    throw std::invalid_argument(std::string(what) + " name '" + name + "' is not a valid HDF5 dataset name");
}

// ---- snapshots ----------------------------------------------------------------------------------

std::string frameFileName(std::size_t index) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%06zu", index);
  return kFramePrefix + std::string(digits) + kFrameSuffix;
}

// frame_<at least 6 digits>.h5 -> its number; anything else (temp files, user files) is ignored.
bool parseFrameFileName(const std::string& name, std::size_t& index) {
  const std::string prefix = kFramePrefix, suffix = kFrameSuffix;
  if (name.size() < prefix.size() + 6 + suffix.size()) return false;
  if (name.compare(0, prefix.size(), prefix) != 0) return false;
  if (name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) return false;
  const char* first = name.data() + prefix.size();
  const char* last = name.data() + name.size() - suffix.size();
  const auto [end, error] = std::from_chars(first, last, index);
  return error == std::errc() && end == last;
}

// Sorted by number, which is the order they were written in.
std::vector<std::pair<std::size_t, fs::path>> listFrameFiles(const fs::path& dir) {
  std::vector<std::pair<std::size_t, fs::path>> frames;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    std::size_t index = 0;
    if (entry.is_regular_file() && parseFrameFileName(entry.path().filename().string(), index))
      frames.emplace_back(index, entry.path());
  }
  std::sort(frames.begin(), frames.end());
  return frames;
}

void validateFrame(const FieldFrame& frame) {
  if (frame.position.size() != frame.count * 3)
    throw std::invalid_argument("FieldFrame: position holds " + std::to_string(frame.position.size()) +
                                " values, expected count * 3 = " + std::to_string(frame.count * 3));
  std::set<std::string> names{"position"};
  for (const FieldArray& array : frame.arrays) {
    requireLinkName(array.name, "FieldArray");
    if (!names.insert(array.name).second)
      throw std::invalid_argument("FieldFrame: array name '" + array.name + "' is used twice (or is 'position')");
    if (array.components != 1 && array.components != 3)
      throw std::invalid_argument("FieldArray '" + array.name + "': components must be 1 or 3");
    if (array.data.size() != frame.count * static_cast<std::size_t>(array.components))
      throw std::invalid_argument("FieldArray '" + array.name + "': holds " + std::to_string(array.data.size()) +
                                  " values, expected count * components");
  }
}

void writeFloatField(hid_t file, const std::string& name, const std::vector<float>& data, std::size_t count,
                     int components, const Where& where) {
  const hsize_t dims[2] = {static_cast<hsize_t>(count), static_cast<hsize_t>(components)};
  writeDataset(file, name, data.data(), components == 1 ? 1 : 2, dims, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, where);
}

void writeFrameFile(const fs::path& path, const FieldFrame& frame) {
  const fs::path tmp = tempPathFor(path);
  const Where where{tmp.string(), Blame::Output};
  // Tracking link creation order lets a restart list the arrays in their original order.
  Hid fcpl(need(H5Pcreate(H5P_FILE_CREATE), where, "cannot create property list"), H5Pclose);
  need(H5Pset_link_creation_order(fcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED), where,
       "cannot set link creation order");
  Hid file(need(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, fcpl.get(), H5P_DEFAULT), where, "cannot create file"),
           H5Fclose);
  writeAttribute(file.get(), "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &frame.time, where);
  writeAttribute(file.get(), "step", H5T_STD_I64LE, H5T_NATIVE_INT64, &frame.step, where);
  writeFloatField(file.get(), "position", frame.position, frame.count, 3, where);
  for (const FieldArray& array : frame.arrays)
    writeFloatField(file.get(), array.name, array.data, frame.count, array.components, where);
  need(file.close(), where, "cannot finish writing");
  renameInto(tmp, path);
}

// ---- XDMF ---------------------------------------------------------------------------------------

std::string xmlEscape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// Shortest text that parses back to the same double, so the index times match the h5 attributes.
std::string exactDouble(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string dimensions(std::size_t count, int components) {
  return components == 1 ? std::to_string(count) : std::to_string(count) + " " + std::to_string(components);
}

void writeDataItem(std::ostream& out, const std::string& dims, const std::string& file, const std::string& set) {
  out << "          <DataItem Dimensions=\"" << dims << "\" NumberType=\"Float\" Precision=\"4\" Format=\"HDF\">"
      << xmlEscape(file) << ":/" << xmlEscape(set) << "</DataItem>\n";
}

void writeFileAtomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = tempPathFor(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw std::runtime_error(tmp.string() + ": cannot write");
  }
  renameInto(tmp, path);
}

}  // namespace

// ---- FieldsWriter -------------------------------------------------------------------------------

FieldsWriter::FieldsWriter(fs::path out_dir, bool append) : m_out(std::move(out_dir)) {
  fs::create_directories(m_out / "fields");
  if (append)
    scanExisting();
  else
    removeStaleFrames();
  // Written now so the index always matches the folder, even before the first snapshot.
  writeXdmf();
}

void FieldsWriter::write(const FieldFrame& frame) {
  validateFrame(frame);
  const std::string file = "fields/" + frameFileName(m_next_index);
  writeFrameFile(m_out / file, frame);
  ++m_next_index;
  Entry entry{frame.time, file, frame.count, {}};
  for (const FieldArray& array : frame.arrays) entry.arrays.emplace_back(array.name, array.components);
  addEntry(std::move(entry));
  writeXdmf();
}

// Entries stay sorted by time: a newer snapshot at or before an indexed time means a restart
// went back to a checkpoint, and its data replaces what the crashed run wrote after that point.
void FieldsWriter::addEntry(Entry entry) {
  while (!m_frames.empty() && m_frames.back().time >= entry.time) m_frames.pop_back();
  m_frames.push_back(std::move(entry));
}

void FieldsWriter::scanExisting() {
  const QuietHdf5Errors quiet;
  for (const auto& [index, path] : listFrameFiles(m_out / "fields")) {
    const Where where{path.string(), Blame::Input};
    if (!isHdf5(path)) fail(where, "not an HDF5 file; cannot index it for the restart (remove it?)");
    Hid file(need(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), where, "cannot open"), H5Fclose);
    Entry entry{readAttribute<double>(file.get(), "time", H5T_NATIVE_DOUBLE, where),
                "fields/" + path.filename().string(), 0, {}};
    const std::vector<hsize_t> pos = datasetDims(file.get(), "position", where);
    if (pos.size() != 2 || pos[1] != 3) fail(where, "/position is not count x 3");
    entry.count = static_cast<std::size_t>(pos[0]);
    for (const std::string& name : linkNames(file.get(), where)) {
      if (name == "position") continue;
      const std::vector<hsize_t> dims = datasetDims(file.get(), name, where);
      const bool shaped = (dims.size() == 1 || (dims.size() == 2 && dims[1] == 3)) && dims[0] == pos[0];
      if (!shaped) fail(where, "/" + name + " is neither count nor count x 3");
      entry.arrays.emplace_back(name, dims.size() == 1 ? 1 : 3);
    }
    addEntry(std::move(entry));
    m_next_index = index + 1;
  }
}

void FieldsWriter::removeStaleFrames() {
  for (const auto& frame : listFrameFiles(m_out / "fields")) fs::remove(frame.second);
}

void FieldsWriter::writeXdmf() const {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<Xdmf Version=\"3.0\">\n"
      << "  <Domain>\n"
      << "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const Entry& e : m_frames) {
    out << "      <Grid Name=\"" << xmlEscape(fs::path(e.file).stem().string()) << "\" GridType=\"Uniform\">\n"
        << "        <Time Value=\"" << exactDouble(e.time) << "\"/>\n"
        << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << e.count
        << "\" NodesPerElement=\"1\"/>\n"
        << "        <Geometry GeometryType=\"XYZ\">\n";
    writeDataItem(out, dimensions(e.count, 3), e.file, "position");
    out << "        </Geometry>\n";
    for (const auto& [name, components] : e.arrays) {
      out << "        <Attribute Name=\"" << xmlEscape(name) << "\" AttributeType=\""
          << (components == 1 ? "Scalar" : "Vector") << "\" Center=\"Node\">\n";
      writeDataItem(out, dimensions(e.count, components), e.file, name);
      out << "        </Attribute>\n";
    }
    out << "      </Grid>\n";
  }
  out << "    </Grid>\n"
      << "  </Domain>\n"
      << "</Xdmf>\n";
  writeFileAtomically(m_out / "fields.xdmf", out.str());
}

// ---- checkpoints --------------------------------------------------------------------------------

namespace {

void writeCheckpointFile(const fs::path& tmp, const CheckpointData& data) {
  const Where where{tmp.string(), Blame::Output};
  Hid file(need(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), where, "cannot create file"),
           H5Fclose);
  writeAttribute(file.get(), "millsim_checkpoint", H5T_STD_I32LE, H5T_NATIVE_INT, &kCheckpointFormat, where);
  writeAttribute(file.get(), "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &data.time, where);
  writeAttribute(file.get(), "step", H5T_STD_I64LE, H5T_NATIVE_INT64, &data.step, where);
  Hid scalars = createGroup(file.get(), "scalars", where);
  for (const auto& [name, value] : data.scalars)
    writeAttribute(scalars.get(), name.c_str(), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value, where);
  Hid reals = createGroup(file.get(), "reals", where);
  for (const auto& [name, values] : data.reals) {
    const hsize_t dims[1] = {static_cast<hsize_t>(values.size())};
    writeDataset(reals.get(), name, values.data(), 1, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, where);
  }
  Hid ints = createGroup(file.get(), "ints", where);
  for (const auto& [name, values] : data.ints) {
    const hsize_t dims[1] = {static_cast<hsize_t>(values.size())};
    writeDataset(ints.get(), name, values.data(), 1, dims, H5T_STD_I64LE, H5T_NATIVE_INT64, where);
  }
  scalars.close();
  reals.close();
  ints.close();
  need(file.close(), where, "cannot finish writing");
}

// Missing file, not HDF5, no marker, newer format: each gets its own message naming the file.
void requireCheckpointFile(const fs::path& path, const Where& where) {
  std::error_code error;
  if (!fs::exists(path, error)) fail(where, "checkpoint file not found");
  if (!fs::is_regular_file(path, error)) fail(where, "not a regular file, so not a millsim checkpoint");
  if (!isHdf5(path)) fail(where, "not an HDF5 file, so not a millsim checkpoint");
}

void requireMarker(hid_t file, const Where& where) {
  if (H5Aexists(file, "millsim_checkpoint") <= 0)
    fail(where, "not a millsim checkpoint (no millsim_checkpoint attribute)");
  const int format = readAttribute<int>(file, "millsim_checkpoint", H5T_NATIVE_INT, where);
  if (format != kCheckpointFormat)
    fail(where, "millsim checkpoint format " + std::to_string(format) + " is not supported (this build reads " +
                    std::to_string(kCheckpointFormat) + ")");
}

}  // namespace

void writeCheckpoint(const fs::path& path, const CheckpointData& data) {
  for (const auto& entry : data.reals) requireLinkName(entry.first, "checkpoint real");
  for (const auto& entry : data.ints) requireLinkName(entry.first, "checkpoint int");
  for (const auto& entry : data.scalars)
    if (entry.first.empty()) throw std::invalid_argument("checkpoint scalar with an empty name");
  const fs::path tmp = tempPathFor(path);
  writeCheckpointFile(tmp, data);
  renameInto(tmp, path);
}

CheckpointData readCheckpoint(const fs::path& path) {
  const Where where{path.string(), Blame::Input};
  const QuietHdf5Errors quiet;
  requireCheckpointFile(path, where);
  Hid file(need(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), where, "cannot open HDF5 file"), H5Fclose);
  requireMarker(file.get(), where);
  CheckpointData data;
  data.time = readAttribute<double>(file.get(), "time", H5T_NATIVE_DOUBLE, where);
  data.step = readAttribute<std::int64_t>(file.get(), "step", H5T_NATIVE_INT64, where);
  Hid scalars = openGroup(file.get(), "scalars", where);
  for (const std::string& name : attributeNames(scalars.get(), where))
    data.scalars[name] = readAttribute<double>(scalars.get(), name.c_str(), H5T_NATIVE_DOUBLE, where);
  Hid reals = openGroup(file.get(), "reals", where);
  for (const std::string& name : linkNames(reals.get(), where))
    data.reals[name] = readVector<double>(reals.get(), name, H5T_NATIVE_DOUBLE, where);
  Hid ints = openGroup(file.get(), "ints", where);
  for (const std::string& name : linkNames(ints.get(), where))
    data.ints[name] = readVector<std::int64_t>(ints.get(), name, H5T_NATIVE_INT64, where);
  return data;
}

bool hdf5ThreadSafe() {
  hbool_t safe = 0;
  return H5is_library_threadsafe(&safe) >= 0 && safe;
}

}  // namespace millsim::io
