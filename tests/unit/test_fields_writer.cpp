// HDF5 snapshots + XDMF index (FieldsWriter) and checkpoints: values read back bit-exactly with
// the HDF5 C API, the index checked as text and through a real XML parser (every DataItem must
// name an existing file and dataset of the stated shape), h5dump accepting the files, restarts
// that append to an earlier run, and the errors a user sees for a bad --restart file.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tinyxml2.h>
#include <unistd.h>

// Debian installs the serial HDF5 headers under hdf5/serial/; the build may not add that path to
// the test target, and hdf5.h finds its siblings with quoted includes either way.
#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "millsim/core/error.hpp"
#include "millsim/io/fields_writer.hpp"
#include "support/shell_command.hpp"

namespace fs = std::filesystem;
namespace mio = millsim::io;

namespace {

// A fresh directory per test, removed afterwards; the test name keeps parallel ctest runs apart.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_path = fs::temp_directory_path() /
             ("millsim_fields_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
              std::to_string(::getpid()));
    fs::remove_all(m_path);
    fs::create_directories(m_path);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(m_path, ignored);
  }
  const fs::path& path() const { return m_path; }

 private:
  fs::path m_path;
};

// Values that are distinct per frame, particle and component, and not round in binary, so a
// transposed or shifted read cannot pass.
mio::FieldFrame makeFrame(double time, std::int64_t step, std::size_t count) {
  mio::FieldFrame f;
  f.time = time;
  f.step = step;
  f.count = count;
  mio::FieldArray velocity{"velocity", 3, {}};
  mio::FieldArray radius{"radius", 1, {}};
  for (std::size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) {
      f.position.push_back(static_cast<float>(time + 0.1 * static_cast<double>(i) + 0.013 * c));
      velocity.data.push_back(static_cast<float>(-1.7 * time + 0.3 * static_cast<double>(i) - 0.07 * c));
    }
    radius.data.push_back(static_cast<float>(0.001 + 0.0001 * static_cast<double>(i) + 0.01 * time));
  }
  f.arrays = {velocity, radius};
  return f;
}

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t countOf(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// Closes an HDF5 id at scope exit so a failed ASSERT does not leak open files between tests.
struct H5Id {
  hid_t id;
  herr_t (*closer)(hid_t);
  ~H5Id() {
    if (id >= 0) closer(id);
  }
};

struct Dataset {
  std::vector<hsize_t> dims;
  std::vector<float> values;
};

Dataset readFloatDataset(const fs::path& file, const std::string& name) {
  H5Id f{H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  H5Id d{f.id >= 0 ? H5Dopen2(f.id, name.c_str(), H5P_DEFAULT) : -1, H5Dclose};
  Dataset out;
  if (d.id < 0) return out;
  H5Id space{H5Dget_space(d.id), H5Sclose};
  out.dims.resize(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space.id)));
  H5Sget_simple_extent_dims(space.id, out.dims.data(), nullptr);
  out.values.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.id)));
  if (!out.values.empty()) H5Dread(d.id, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.values.data());
  return out;
}

template <class T>
T readRootAttribute(const fs::path& file, const char* name, hid_t mem_type) {
  H5Id f{H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  H5Id a{H5Aopen(f.id, name, H5P_DEFAULT), H5Aclose};
  T value{};
  H5Aread(a.id, mem_type, &value);
  return value;
}

void expectFrameOnDisk(const fs::path& file, const mio::FieldFrame& frame) {
  SCOPED_TRACE(file.string());
  ASSERT_TRUE(fs::exists(file));
  EXPECT_EQ(readRootAttribute<double>(file, "time", H5T_NATIVE_DOUBLE), frame.time);
  EXPECT_EQ(readRootAttribute<std::int64_t>(file, "step", H5T_NATIVE_INT64), frame.step);
  const Dataset pos = readFloatDataset(file, "position");
  EXPECT_EQ(pos.dims, (std::vector<hsize_t>{frame.count, 3}));
  EXPECT_EQ(pos.values, frame.position);
  for (const mio::FieldArray& a : frame.arrays) {
    const Dataset d = readFloatDataset(file, a.name);
    const std::vector<hsize_t> dims =
        a.components == 1 ? std::vector<hsize_t>{frame.count} : std::vector<hsize_t>{frame.count, 3};
    EXPECT_EQ(d.dims, dims) << a.name;
    EXPECT_EQ(d.values, a.data) << a.name;
  }
}

// One <Grid> of the temporal collection, as a reader such as ParaView sees it.
struct XdmfGrid {
  double time = -1;
  std::size_t elements = 0;
  std::vector<std::string> data_paths;  // "fields/frame_000000.h5:/position", ...
  std::vector<std::string> data_dims;
  std::vector<std::string> attribute_names;
};

// A missing element throws, which gtest reports as a failure of the test instead of a crash.
const tinyxml2::XMLElement* child(const tinyxml2::XMLElement* parent, const char* name) {
  const tinyxml2::XMLElement* found = parent->FirstChildElement(name);
  if (!found) throw std::runtime_error(std::string("XDMF: <") + parent->Name() + "> has no <" + name + ">");
  return found;
}

std::string attribute(const tinyxml2::XMLElement* element, const char* name) {
  const char* value = element->Attribute(name);
  if (!value) throw std::runtime_error(std::string("XDMF: <") + element->Name() + "> has no " + name);
  return value;
}

XdmfGrid parseGrid(const tinyxml2::XMLElement* g) {
  XdmfGrid grid;
  EXPECT_EQ(attribute(g, "GridType"), "Uniform");
  grid.time = child(g, "Time")->DoubleAttribute("Value", -1);
  const auto* topology = child(g, "Topology");
  EXPECT_EQ(attribute(topology, "TopologyType"), "Polyvertex");
  grid.elements = std::stoull(attribute(topology, "NumberOfElements"));
  const auto* geometry = child(g, "Geometry");
  EXPECT_EQ(attribute(geometry, "GeometryType"), "XYZ");
  auto addItem = [&grid](const tinyxml2::XMLElement* item) {
    EXPECT_EQ(attribute(item, "Format"), "HDF");
    grid.data_paths.emplace_back(item->GetText() ? item->GetText() : "");
    grid.data_dims.emplace_back(attribute(item, "Dimensions"));
  };
  addItem(child(geometry, "DataItem"));
  for (auto* a = g->FirstChildElement("Attribute"); a; a = a->NextSiblingElement("Attribute")) {
    EXPECT_EQ(attribute(a, "Center"), "Node");
    const std::string type = attribute(a, "AttributeType");
    EXPECT_TRUE(type == "Scalar" || type == "Vector") << type;
    grid.attribute_names.emplace_back(attribute(a, "Name"));
    addItem(child(a, "DataItem"));
    const std::string& dims = grid.data_dims.back();
    EXPECT_EQ(type == "Vector", dims.find(' ') != std::string::npos) << dims;
  }
  return grid;
}

std::vector<XdmfGrid> parseXdmf(const fs::path& path) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS)
    throw std::runtime_error(path.string() + ": " + doc.ErrorStr());
  const tinyxml2::XMLElement* root = doc.FirstChildElement("Xdmf");
  if (!root) throw std::runtime_error(path.string() + ": no <Xdmf> root");
  const tinyxml2::XMLElement* collection = child(child(root, "Domain"), "Grid");
  EXPECT_EQ(attribute(collection, "GridType"), "Collection");
  EXPECT_EQ(attribute(collection, "CollectionType"), "Temporal");
  std::vector<XdmfGrid> grids;
  for (auto* g = collection->FirstChildElement("Grid"); g; g = g->NextSiblingElement("Grid"))
    grids.push_back(parseGrid(g));
  return grids;
}

std::string dimsText(const std::vector<hsize_t>& dims) {
  std::string s;
  for (hsize_t d : dims) s += (s.empty() ? "" : " ") + std::to_string(d);
  return s;
}

// Every DataItem must resolve, relative to the .xdmf, to an existing dataset of its stated shape.
void expectDataItemsResolve(const fs::path& xdmf, const std::vector<XdmfGrid>& grids) {
  for (const XdmfGrid& g : grids) {
    ASSERT_EQ(g.data_paths.size(), g.data_dims.size());
    for (std::size_t i = 0; i < g.data_paths.size(); ++i) {
      const std::string& item = g.data_paths[i];
      const std::size_t colon = item.find(":/");
      ASSERT_NE(colon, std::string::npos) << item;
      const fs::path file = xdmf.parent_path() / item.substr(0, colon);
      ASSERT_TRUE(fs::is_regular_file(file)) << item;
      EXPECT_TRUE(fs::path(item.substr(0, colon)).is_relative()) << item;
      const Dataset d = readFloatDataset(file, item.substr(colon + 2));
      ASSERT_FALSE(d.dims.empty()) << item << " names no dataset";
      EXPECT_EQ(dimsText(d.dims), g.data_dims[i]) << item;
    }
  }
}

std::string findProgram(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && fs::exists(fs::path(dir) / name)) return (fs::path(dir) / name).string();
  return fs::exists("/usr/bin/" + name) ? "/usr/bin/" + name : "";
}

mio::CheckpointData sampleCheckpoint() {
  mio::CheckpointData cp;
  cp.time = 1.2345678901234567;
  cp.step = 9876543210123LL;
  cp.scalars = {{"phi", -3.25e-7}, {"dt", 2.5e-6}, {"frames_taken", 17.0}};
  cp.reals = {{"pos", {0.1, -0.2, 1e300, 5e-324, -0.0}}, {"empty", {}}, {"mass", {7.5}}};
  cp.ints = {{"hist_id", {-1, 0, 9223372036854775807LL, -9223372036854775807LL - 1}}, {"none", {}}};
  return cp;
}

void expectInputErrorNaming(const fs::path& path, const std::string& fragment) {
  try {
    mio::readCheckpoint(path);
    ADD_FAILURE() << "readCheckpoint(" << path << ") did not throw";
  } catch (const millsim::core::InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path.string(), 0), 0u) << "message should start with the path: " << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

}  // namespace

TEST(FieldsWriter, TwoFramesRoundTripExactlyAndAreIndexed) {
  TempDir dir;
  const mio::FieldFrame f0 = makeFrame(0.25, 100, 5), f1 = makeFrame(0.5, 200, 5);
  {
    mio::FieldsWriter writer(dir.path());
    writer.write(f0);
    writer.write(f1);
    EXPECT_EQ(writer.framesWritten(), 2u);
  }
  expectFrameOnDisk(dir.path() / "fields/frame_000000.h5", f0);
  expectFrameOnDisk(dir.path() / "fields/frame_000001.h5", f1);
  EXPECT_FALSE(fs::exists(dir.path() / "fields.xdmf.tmp"));
  EXPECT_FALSE(fs::exists(dir.path() / "fields/frame_000001.h5.tmp"));

  const std::string xdmf = readText(dir.path() / "fields.xdmf");
  EXPECT_NE(xdmf.find("fields/frame_000000.h5:/position"), std::string::npos) << xdmf;
  EXPECT_NE(xdmf.find("fields/frame_000001.h5:/position"), std::string::npos) << xdmf;
  EXPECT_NE(xdmf.find("fields/frame_000001.h5:/velocity"), std::string::npos) << xdmf;
  EXPECT_NE(xdmf.find("fields/frame_000001.h5:/radius"), std::string::npos) << xdmf;
  EXPECT_EQ(countOf(xdmf, "<Time "), 2u);
  EXPECT_NE(xdmf.find("<Time Value=\"0.25\"/>"), std::string::npos) << xdmf;
  EXPECT_NE(xdmf.find("<Time Value=\"0.5\"/>"), std::string::npos) << xdmf;
  EXPECT_EQ(countOf(xdmf, "NumberOfElements=\"5\""), 2u);
  EXPECT_EQ(countOf(xdmf, "Dimensions=\"5 3\""), 4u);  // position + velocity, per frame
  EXPECT_EQ(countOf(xdmf, "Dimensions=\"5\""), 2u);    // radius, per frame
  EXPECT_EQ(countOf(xdmf, "CollectionType=\"Temporal\""), 1u);
}

TEST(FieldsWriter, H5dumpReadsTheSnapshot) {
  const std::string h5dump = findProgram("h5dump");
  if (h5dump.empty())
    GTEST_SKIP() << "h5dump not found (Debian package hdf5-tools); skipping the external-reader check";
  TempDir dir;
  {
    mio::FieldsWriter writer(dir.path());
    writer.write(makeFrame(0.25, 100, 5));
  }
  const auto [status, output] = millsim::testing::runShell(h5dump + " -H '" + (dir.path() / "fields/frame_000000.h5").string() + "'");
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("DATASET \"position\""), std::string::npos) << output;
  EXPECT_NE(output.find("( 5, 3 )"), std::string::npos) << output;
  EXPECT_NE(output.find("DATASET \"radius\""), std::string::npos) << output;
  EXPECT_NE(output.find("ATTRIBUTE \"time\""), std::string::npos) << output;
  EXPECT_NE(output.find("ATTRIBUTE \"step\""), std::string::npos) << output;
}

TEST(FieldsWriter, XdmfParsesAndEveryDataItemResolves) {
  TempDir dir;
  {
    mio::FieldsWriter writer(dir.path());
    writer.write(makeFrame(0.25, 100, 5));
    writer.write(makeFrame(0.5, 200, 5));
  }
  const fs::path xdmf = dir.path() / "fields.xdmf";
  const std::vector<XdmfGrid> grids = parseXdmf(xdmf);
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[0].time, 0.25);
  EXPECT_EQ(grids[1].time, 0.5);
  for (const XdmfGrid& g : grids) {
    EXPECT_EQ(g.elements, 5u);
    EXPECT_EQ(g.attribute_names, (std::vector<std::string>{"velocity", "radius"}));
    EXPECT_EQ(g.data_dims, (std::vector<std::string>{"5 3", "5 3", "5"}));
  }
  EXPECT_EQ(grids[1].data_paths[0], "fields/frame_000001.h5:/position");
  expectDataItemsResolve(xdmf, grids);
}

TEST(FieldsWriter, ZeroParticlesStillGiveValidFiles) {
  TempDir dir;
  mio::FieldFrame empty = makeFrame(0.0, 0, 0);
  {
    mio::FieldsWriter writer(dir.path());
    writer.write(empty);
  }
  expectFrameOnDisk(dir.path() / "fields/frame_000000.h5", empty);
  const std::vector<XdmfGrid> grids = parseXdmf(dir.path() / "fields.xdmf");
  ASSERT_EQ(grids.size(), 1u);
  EXPECT_EQ(grids[0].elements, 0u);
  EXPECT_EQ(grids[0].data_dims, (std::vector<std::string>{"0 3", "0 3", "0"}));
  expectDataItemsResolve(dir.path() / "fields.xdmf", grids);
}

TEST(FieldsWriter, RejectsInconsistentFrames) {
  TempDir dir;
  mio::FieldsWriter writer(dir.path());
  mio::FieldFrame bad = makeFrame(0.1, 1, 4);
  bad.position.pop_back();
  EXPECT_THROW(writer.write(bad), std::invalid_argument);
  bad = makeFrame(0.1, 1, 4);
  bad.arrays[1].data.push_back(1.0f);
  EXPECT_THROW(writer.write(bad), std::invalid_argument);
  bad = makeFrame(0.1, 1, 4);
  bad.arrays[0].name = "a/b";
  EXPECT_THROW(writer.write(bad), std::invalid_argument);
  bad = makeFrame(0.1, 1, 4);
  bad.arrays[1].name = "position";
  EXPECT_THROW(writer.write(bad), std::invalid_argument);
  EXPECT_EQ(writer.framesWritten(), 0u);
  EXPECT_FALSE(fs::exists(dir.path() / "fields/frame_000000.h5"));
}

TEST(Checkpoint, RoundTripIsExactIncludingEmptyVectors) {
  TempDir dir;
  const fs::path path = dir.path() / "checkpoint.h5";
  const mio::CheckpointData cp = sampleCheckpoint();
  mio::writeCheckpoint(path, cp);
  EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
  const mio::CheckpointData back = mio::readCheckpoint(path);
  EXPECT_EQ(back.time, cp.time);
  EXPECT_EQ(back.step, cp.step);
  EXPECT_EQ(back.scalars, cp.scalars);
  EXPECT_EQ(back.reals, cp.reals);
  EXPECT_EQ(back.ints, cp.ints);
  EXPECT_EQ(readRootAttribute<int>(path, "millsim_checkpoint", H5T_NATIVE_INT), 1);

  // Overwriting replaces the whole content: nothing of the first checkpoint survives.
  mio::CheckpointData second;
  second.time = 2.0;
  second.reals["vel"] = {4.0};
  mio::writeCheckpoint(path, second);
  const mio::CheckpointData back2 = mio::readCheckpoint(path);
  EXPECT_EQ(back2.time, 2.0);
  EXPECT_EQ(back2.step, 0);
  EXPECT_TRUE(back2.scalars.empty());
  EXPECT_TRUE(back2.ints.empty());
  EXPECT_EQ(back2.reals, (std::map<std::string, std::vector<double>>{{"vel", {4.0}}}));
}

TEST(Checkpoint, BadFilesThrowInputErrorNamingThePath) {
  TempDir dir;
  expectInputErrorNaming(dir.path() / "missing.h5", "not found");

  const fs::path text = dir.path() / "notes.h5";
  std::ofstream(text) << "time,step\n0.1,10\n";
  expectInputErrorNaming(text, "not an HDF5 file");

  // A valid HDF5 file from somewhere else (here: a field snapshot) lacks the marker.
  {
    mio::FieldsWriter writer(dir.path());
    writer.write(makeFrame(0.25, 100, 2));
  }
  expectInputErrorNaming(dir.path() / "fields/frame_000000.h5",
                         "not a millsim checkpoint (no millsim_checkpoint attribute)");
}

TEST(FieldsWriter, AppendContinuesNumberingAndKeepsEarlierFrames) {
  TempDir dir;
  const mio::FieldFrame f0 = makeFrame(0.1, 10, 5), f1 = makeFrame(0.2, 20, 5), f2 = makeFrame(0.3, 30, 5);
  {
    mio::FieldsWriter writer(dir.path());
    writer.write(f0);
    writer.write(f1);
  }
  const std::string before = readText(dir.path() / "fields.xdmf");
  mio::FieldsWriter restarted(dir.path(), /*append=*/true);
  EXPECT_EQ(restarted.framesWritten(), 2u);
  // The index rebuilt from the files alone matches the one the first run wrote.
  EXPECT_EQ(readText(dir.path() / "fields.xdmf"), before);
  restarted.write(f2);
  EXPECT_EQ(restarted.framesWritten(), 3u);
  expectFrameOnDisk(dir.path() / "fields/frame_000000.h5", f0);
  expectFrameOnDisk(dir.path() / "fields/frame_000002.h5", f2);

  const std::vector<XdmfGrid> grids = parseXdmf(dir.path() / "fields.xdmf");
  ASSERT_EQ(grids.size(), 3u);
  EXPECT_EQ(grids[0].time, 0.1);
  EXPECT_EQ(grids[1].time, 0.2);
  EXPECT_EQ(grids[2].time, 0.3);
  EXPECT_EQ(grids[2].data_paths[0], "fields/frame_000002.h5:/position");
  EXPECT_EQ(grids[0].attribute_names, (std::vector<std::string>{"velocity", "radius"}));
  expectDataItemsResolve(dir.path() / "fields.xdmf", grids);
}

TEST(FieldsWriter, RestartFromOlderCheckpointSupersedesLaterFrames) {
  TempDir dir;
  {
    mio::FieldsWriter writer(dir.path());
    for (int i = 0; i < 3; ++i) writer.write(makeFrame(0.1 * (i + 1), 10 * (i + 1), 3));
  }
  // The checkpoint was at t = 0.2: the restart writes t = 0.2 again, then moves on.
  mio::FieldsWriter restarted(dir.path(), true);
  restarted.write(makeFrame(0.2, 20, 4));
  const std::vector<XdmfGrid> grids = parseXdmf(dir.path() / "fields.xdmf");
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[0].time, 0.1);
  EXPECT_EQ(grids[1].time, 0.2);
  EXPECT_EQ(grids[1].elements, 4u);
  EXPECT_EQ(grids[1].data_paths[0], "fields/frame_000003.h5:/position");  // no file is overwritten
  EXPECT_TRUE(fs::exists(dir.path() / "fields/frame_000002.h5"));

  // A second restart rebuilds the same index from the files.
  mio::FieldsWriter again(dir.path(), true);
  EXPECT_EQ(again.framesWritten(), 2u);
  EXPECT_EQ(parseXdmf(dir.path() / "fields.xdmf")[1].data_paths[0], "fields/frame_000003.h5:/position");
}

TEST(FieldsWriter, FreshRunDropsSnapshotsOfAnEarlierRun) {
  TempDir dir;
  {
    mio::FieldsWriter writer(dir.path());
    for (int i = 0; i < 3; ++i) writer.write(makeFrame(0.1 * (i + 1), i, 2));
  }
  mio::FieldsWriter fresh(dir.path());
  EXPECT_EQ(fresh.framesWritten(), 0u);
  EXPECT_FALSE(fs::exists(dir.path() / "fields/frame_000002.h5"));
  EXPECT_TRUE(parseXdmf(dir.path() / "fields.xdmf").empty());
  fresh.write(makeFrame(0.05, 1, 2));
  EXPECT_TRUE(fs::exists(dir.path() / "fields/frame_000000.h5"));
  EXPECT_EQ(parseXdmf(dir.path() / "fields.xdmf").size(), 1u);
}
