// The HDF5 helper every .h5 file goes through: datasets, strings and attributes round-trip,
// a failed write leaves nothing behind, and bad files are one-line errors naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>
#include <string>
#include <vector>

#include "pb4u/io/hdf5_file.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

// The message of the pb4u::Error f throws ("" and a test failure when it throws none).
template <class F>
std::string hdf5_error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no pb4u::Error";
  return "";
}

TEST(Hdf5File, DatasetsStringsAndAttributesRoundTrip) {
  const std::string path = test::temp_dir("hdf5_file") + "/a.h5";
  const std::vector<double> positions{0.5, -1.25, 3e-9, 4, 5, 6};
  std::vector<int32_t> big(5000);
  for (size_t i = 0; i < big.size(); ++i) big[i] = static_cast<int32_t>(i) - 7;
  write_hdf5(path, [&](Hdf5Group& root) {
    root.set_attribute("format", std::string("pb4u-test"));
    root.set_attribute("empty", std::string());
    root.set_attribute("fps", 24.0);
    root.set_attribute("version", 3);
    Hdf5Group g = root.create_group("garment");
    g.write("positions", {1, 2, 3}, positions.data());
    g.write("faces", {2500, 2}, big.data(), true);  // chunked and deflated
    const std::vector<float> weights{0.25f, 0.75f};
    g.write("weights", {2}, weights.data());
    const std::vector<int64_t> count{42};
    root.write("count", {1}, count.data());
    root.write_strings("names", {"hips", "", "left_upper_arm"});
  });
  EXPECT_TRUE(is_hdf5_file(path));

  const Hdf5Group root = open_hdf5(path);
  EXPECT_EQ(root.file(), path);
  EXPECT_EQ(root.name(), "/");
  EXPECT_EQ(root.string_attribute("format"), "pb4u-test");
  EXPECT_EQ(root.string_attribute("empty"), "");
  EXPECT_EQ(root.double_attribute("fps"), 24.0);
  EXPECT_EQ(root.double_attribute("version"), 3.0);
  const auto strings = root.string_attributes();  // the numbers are skipped
  EXPECT_EQ(strings.size(), 2u);
  EXPECT_EQ(strings.at("format"), "pb4u-test");
  EXPECT_EQ(root.children(), (std::vector<std::string>{"count", "garment", "names"}));
  EXPECT_EQ(root.read_strings("names"), (std::vector<std::string>{"hips", "", "left_upper_arm"}));

  ASSERT_TRUE(root.has("garment"));
  const Hdf5Group g = root.group("garment");
  EXPECT_EQ(g.name(), "/garment");
  EXPECT_EQ(g.shape("positions"), (std::vector<size_t>{1, 2, 3}));
  std::vector<double> x(6);
  g.read("positions", x.data());
  EXPECT_EQ(x, positions);
  std::vector<int32_t> f(big.size());
  g.read("faces", f.data());
  EXPECT_EQ(f, big);
  std::vector<double> w(2);  // float32 read as float64
  g.read("weights", w.data());
  EXPECT_EQ(w, (std::vector<double>{0.25, 0.75}));
  int64_t count = 0;
  root.read("count", &count);
  EXPECT_EQ(count, 42);
}

TEST(Hdf5File, MissingObjectsNameTheFileAndThePath) {
  const std::string path = test::temp_dir("hdf5_file") + "/b.h5";
  write_hdf5(path, [](Hdf5Group& root) { root.create_group("bodies"); });
  const Hdf5Group root = open_hdf5(path);
  EXPECT_EQ(hdf5_error_of([&] { root.group("motions"); }), path + ": /motions: missing");
  EXPECT_EQ(hdf5_error_of([&] { root.group("bodies").shape("vertices"); }),
            path + ": /bodies/vertices: missing");
  EXPECT_EQ(hdf5_error_of([&] { root.string_attribute("format"); }),
            path + ": /: attribute 'format' missing");
}

TEST(Hdf5File, BadFilesAreOneLineErrorsNamingTheFile) {
  const std::string dir = test::temp_dir("hdf5_bad");
  test::write_file(dir + "/text.h5", "not hdf5 at all");
  test::write_file(dir + "/empty.h5", "");
  const std::string good = dir + "/good.h5";
  const std::vector<double> values(10000, 1.5);
  write_hdf5(good, [&](Hdf5Group& root) { root.write("values", {10000}, values.data()); });
  const std::string bytes = test::read_file(good);
  test::write_file(dir + "/truncated.h5", bytes.substr(0, bytes.size() / 2));
  for (const std::string name : {"missing.h5", "text.h5", "empty.h5", "truncated.h5"}) {
    const std::string path = dir + "/" + name;
    std::vector<double> read(10000);
    const std::string what = hdf5_error_of([&] { open_hdf5(path).read("values", read.data()); });
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  EXPECT_FALSE(is_hdf5_file(dir + "/missing.h5"));
  EXPECT_FALSE(is_hdf5_file(dir + "/text.h5"));
  EXPECT_EQ(hdf5_error_of([&] { open_hdf5(dir + "/missing.h5"); }), dir + "/missing.h5: no such file");
}

TEST(Hdf5File, AFailedWriteLeavesTheOldFile) {
  const std::string dir = test::temp_dir("hdf5_atomic");
  const std::string path = dir + "/c.h5";
  write_hdf5(path, [](Hdf5Group& root) { root.set_attribute("format", std::string("old")); });
  EXPECT_THROW(write_hdf5(path,
                          [](Hdf5Group& root) {
                            root.set_attribute("format", std::string("new"));
                            throw Error("fill failed");
                          }),
               Error);
  // Two datasets of one name: HDF5 refuses the second, named by the final path.
  const std::string what = hdf5_error_of([&] {
    write_hdf5(path, [](Hdf5Group& root) {
      const double v = 1;
      root.write("x", {1}, &v);
      root.write("x", {1}, &v);
    });
  });
  EXPECT_EQ(what.rfind(path + ": /x: ", 0), 0u) << what;
  EXPECT_EQ(open_hdf5(path).string_attribute("format"), "old");
  namespace fs = std::filesystem;
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);  // no temporary left
}

}  // namespace
}  // namespace pb4u
