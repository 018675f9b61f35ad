// Special files, bounded reads, output identities, the commit check and image values (issue 24,
// docs/RELIABILITY.md, "Special files"): the library functions behind the hostile table's rows
// special_*, collide_*, lock_* and image_*.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "brdfbake/cancel.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/output_checks.hpp"
#include "brdfbake/output_lock.hpp"
#include "io/image_file.hpp"
#include "io/ktx1.hpp"
#include "io/png_image.hpp"
#include "io/rgbe.hpp"
#include "io/special_files.hpp"
#include "io/staging_dir.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

void write(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// ---- What a path names ------------------------------------------------------------------------------

TEST(SpecialFiles, TypesAreFoundWithoutOpening) {
  const fs::path d = temp_dir("types");
  write(d / "f", "x");
  ASSERT_EQ(::mkfifo((d / "p").c_str(), 0600), 0);
  EXPECT_EQ(io::file_type((d / "f").string()), io::FileType::Regular);
  EXPECT_EQ(io::file_type(d.string()), io::FileType::Folder);
  EXPECT_EQ(io::file_type((d / "p").string()), io::FileType::Fifo);  // stat: no writer needed
  EXPECT_EQ(io::file_type("/dev/null"), io::FileType::CharDevice);
  EXPECT_EQ(io::file_type((d / "none").string()), io::FileType::Missing);
  // an input that must be a file: the FIFO refused at once, by name
  EXPECT_NE(io::input_problem((d / "p").string(), io::Streams::No).find("FIFO"), std::string::npos);
  EXPECT_EQ(io::input_problem((d / "p").string(), io::Streams::Yes), "");
  EXPECT_EQ(io::input_problem((d / "none").string(), io::Streams::Yes), "no such file");
  EXPECT_EQ(io::input_problem(d.string(), io::Streams::Yes), "it is a folder");
}

TEST(SpecialFiles, OutputTargetsByWhatTheyName) {
  const fs::path d = temp_dir("targets");
  write(d / "f.csv", "x");
  ASSERT_EQ(::mkfifo((d / "p").c_str(), 0600), 0);
  EXPECT_EQ(io::output_target((d / "f.csv").string()).target, io::OutputTarget::File);
  EXPECT_EQ(io::output_target((d / "new.csv").string()).target, io::OutputTarget::File);
  EXPECT_EQ(io::output_target(d.string()).target, io::OutputTarget::File);  // a folder output
  EXPECT_EQ(io::output_target("-").target, io::OutputTarget::Stream);
  EXPECT_EQ(io::output_target("/dev/null").target, io::OutputTarget::Stream);
  EXPECT_EQ(io::output_target((d / "p").string()).target, io::OutputTarget::Stream);
  EXPECT_EQ(io::output_target("/dev/stdout").target, io::OutputTarget::Stream);  // whatever stdout is
  EXPECT_EQ(io::output_target("/dev/brdfbake-no-such-name").target, io::OutputTarget::Refused);
  // a stream target refused where the output is renamed into place
  EXPECT_NE(error_of([] { io::check_output_target("/dev/null", false, "-o"); }).find("character device"),
            std::string::npos);
  EXPECT_EQ(error_of([] { io::check_output_target("/dev/null", true, "-o"); }), "");
  // and by every atomic writer, whoever calls it: the device stays a device
  EXPECT_NE(error_of([] { io::write_file_atomically("/dev/null", "x"); }).find("character device"), std::string::npos);
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
}

// ---- Bounded, cancellable reads --------------------------------------------------------------------

TEST(SpecialFiles, StreamsStopOnePastTheirLimit) {
  // /dev/zero never ends: the read ends with the limit's byte
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_NE(error_of([] {
              io::read_input("/dev/zero", "job", 1 << 20, "1 MiB", io::Streams::Yes);
            }).find("larger than 1 MiB"),
            std::string::npos);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10.0);
  // a regular file over the limit is refused from its size
  const fs::path d = temp_dir("bounded");
  write(d / "big", std::string(100, 'x'));
  EXPECT_NE(error_of([&] {
              io::read_input((d / "big").string(), "job", 99, "99 bytes", io::Streams::Yes);
            }).find("larger than 99 bytes"),
            std::string::npos);
  EXPECT_EQ(io::read_input((d / "big").string(), "job", 100, "100 bytes", io::Streams::Yes).size(), 100u);
  // and a head never allocates what a bound promises beyond the file
  EXPECT_EQ(io::read_input_head((d / "big").string(), "image", size_t(1) << 40, io::Streams::No).size(), 100u);
}

TEST(SpecialFiles, AFifoWithoutWriterWaitsUntilAStop) {
  const fs::path d = temp_dir("fifo");
  ASSERT_EQ(::mkfifo((d / "p").c_str(), 0600), 0);
  reset_cancel();
  std::thread stopper([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    request_cancel(SIGTERM);
  });
  bool cancelled = false;
  try {
    io::read_input((d / "p").string(), "job", 1 << 20, "1 MiB", io::Streams::Yes);
  } catch (const Cancelled& c) {
    cancelled = c.signal() == SIGTERM;
  }
  stopper.join();
  reset_cancel();
  EXPECT_TRUE(cancelled) << "a read that waits for a writer must end on a stop request, as Cancelled";
  // with a writer, the FIFO's bytes are read up to its end
  std::thread writer([&] { std::ofstream(d / "p") << "{\"a\": 1}"; });
  EXPECT_EQ(io::read_input((d / "p").string(), "job", 1 << 20, "1 MiB", io::Streams::Yes), "{\"a\": 1}");
  writer.join();
}

TEST(SpecialFiles, TokenFilesAreBoundedAndPrintable) {
  const fs::path d = temp_dir("token");
  write(d / "t", "0123456789abcdef0123\r\nsecond line\n");
  EXPECT_EQ(io::read_token_file((d / "t").string(), "--token-file"), "0123456789abcdef0123");
  write(d / "nul", std::string("0123456789\0abcdef\n", 18));
  EXPECT_NE(error_of([&] { io::read_token_file((d / "nul").string(), "--token-file"); }).find("control character"),
            std::string::npos);
  EXPECT_NE(error_of([] { io::read_token_file("/dev/zero", "--token-file"); }).find("4 KiB"), std::string::npos);
}

// ---- The commit is checked -------------------------------------------------------------------------

// Files a run wrote that are gone from the folder when the commit ends (another program emptied or
// replaced it meanwhile) are an I/O failure naming the file, never a success.
TEST(StagingCommit, FilesMissingAfterTheMoveAreAFailure) {
  const fs::path d = temp_dir("commit");
  fs::create_directories(d / "out");
  io::StagingDir staging(d / "out");
  write(staging.path() / "t.exr", "table");
  write(staging.path() / "manifest.json", "{}");
  const std::vector<io::MovedFile> moved = io::files_to_move(staging.path(), d / "out", "manifest.json");
  ASSERT_EQ(moved.size(), 2u);
  EXPECT_EQ(moved.back().rel, fs::path("manifest.json"));  // last
  staging.commit("manifest.json");
  EXPECT_EQ(error_of([&] { io::check_moved_in(d / "out", moved); }), "");
  write(d / "other", "another file of that name");  // made while the moved file's inode is in use
  fs::remove(d / "out" / "t.exr");                  // what `rm -rf out` racing the commit did
  const std::string e = error_of([&] { io::check_moved_in(d / "out", moved); });
  EXPECT_NE(e.find("t.exr' is missing"), std::string::npos) << e;
  fs::rename(d / "other", d / "out" / "t.exr");
  EXPECT_NE(error_of([&] { io::check_moved_in(d / "out", moved); }).find("not the file this run wrote"),
            std::string::npos);
}

// ---- Locks by identity --------------------------------------------------------------------------------

TEST(OutputLockIdentity, EveryNameOfOneFolderIsOneLock) {
  const fs::path d = temp_dir("identity");
  fs::create_directories(d / "real");
  fs::create_symlink(d / "real", d / "link");
  fs::create_directories(d / "sub");
  EXPECT_EQ(output_lock_path((d / "link").string()), output_lock_path((d / "real").string()));
  EXPECT_EQ(output_lock_path((d / "sub" / ".." / "real").string()), output_lock_path((d / "real").string()));
  OutputLock held((d / "link").string(), false);
  EXPECT_THROW(OutputLock((d / "real" / "").string(), false), LockedError);
  EXPECT_THROW(OutputLock((d / "sub" / ".." / "link").string(), false), LockedError);
}

// ---- Output sets -------------------------------------------------------------------------------------

TEST(OutputChecks, CaseOfTheFileSystemIsProbed) {
  const fs::path d = temp_dir("case");
  // this machine's temporary folder (ext4, tmpfs) tells names apart by case; the probe leaves nothing
  EXPECT_FALSE(folder_ignores_case((d / "not" / "yet").string()));
  EXPECT_TRUE(fs::is_empty(d));
}

TEST(OutputChecks, AnOutputThatIsAnInputIsRefusedByIdentity) {
  const fs::path d = temp_dir("identity_out");
  write(d / "m.json", R"({"materials": [{"name": "a", "model": "gltf"}]})");
  write(d / "p.csv", "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,1\n");
  fs::create_hard_link(d / "p.csv", d / "hard.csv");
  TableRequest t;
  t.kind = TableKind::Eval;
  t.params = {{"material", (d / "m.json").string()}, {"input", (d / "p.csv").string()}};
  t.output = (d / "hard.csv").string();
  FieldNaming cli;
  cli.cli = true;
  validate_table(t, cli);
  const std::string e = error_of([&] { check_table_files(t, cli, true); });
  EXPECT_NE(e.find("same file as --input"), std::string::npos) << e;
  t.output = (d / "f.csv").string();
  EXPECT_EQ(error_of([&] { check_table_files(t, cli, true); }), "");
}

// ---- Image values ------------------------------------------------------------------------------------

// A PNG written by OpenImageIO with the given colour space (empty: none stated).
fs::path oiio_png(const fs::path& dir, const std::string& name, const std::string& space, int depth) {
  const fs::path p = dir / name;
  auto out = OIIO::ImageOutput::create(p.string());
  OIIO::ImageSpec spec(4, 2, 3, depth == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
  if (!space.empty()) spec.attribute("oiio:ColorSpace", space);
  std::vector<uint16_t> px16(4 * 2 * 3, uint16_t(depth == 16 ? 32896 : 128));  // 128/255 = 32896/65535
  std::vector<uint8_t> px8(4 * 2 * 3, 128);
  EXPECT_TRUE(out && out->open(p.string(), spec));
  EXPECT_TRUE(out->write_image(depth == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8,
                               depth == 16 ? static_cast<void*>(px16.data()) : static_cast<void*>(px8.data())));
  out->close();
  return p;
}

// 128/255 in sRGB is 0.2158605 linear (IEC 61966-2-1: ((c + 0.055) / 1.055)^2.4); read as linear it
// was 0.50196, with no word.
constexpr double kSrgb128 = 0.21586050011389926;

TEST(ImageValues, EightBitSrgbIsDecodedToLinearAndSaid) {
  const fs::path d = temp_dir("srgb");
  for (const std::string& space : {std::string("sRGB"), std::string()}) {
    const io::FloatImage img = io::read_image(oiio_png(d, "s" + space + ".png", space, 8).string(), io::ImageLimits{});
    ASSERT_EQ(img.channels, 3);
    for (float v : img.pixels) EXPECT_NEAR(v, kSrgb128, 1e-6) << "space '" << space << "'";  // float rounding
    EXPECT_NE(img.transfer_note.find("sRGB"), std::string::npos) << img.transfer_note;
    EXPECT_NE(img.description.find("decoded to linear"), std::string::npos) << img.description;
  }
}

TEST(ImageValues, GammaAndLinearChunksAreHonoured) {
  const fs::path d = temp_dir("gamma");
  // OpenImageIO writes gAMA for "Gamma2.2" and gAMA 1.0 for linear data
  const io::FloatImage g = io::read_image(oiio_png(d, "g.png", "Gamma2.2", 8).string(), io::ImageLimits{});
  EXPECT_NEAR(g.pixels[0], std::pow(128.0 / 255.0, 1.0 / 0.45455), 1e-5) << g.description;
  const io::FloatImage l = io::read_image(oiio_png(d, "l.png", "linear", 8).string(), io::ImageLimits{});
  EXPECT_NEAR(l.pixels[0], 128.0 / 255.0, 1e-6) << l.description;
  EXPECT_EQ(l.transfer_note, "") << "linear data needs no word";
  // 16-bit without a colour chunk is read as stored, and said
  const io::FloatImage w = io::read_image(oiio_png(d, "w.png", "", 16).string(), io::ImageLimits{});
  EXPECT_NEAR(w.pixels[0], 32896.0 / 65535.0, 1e-6) << w.description;
  EXPECT_NE(w.transfer_note.find("read as linear"), std::string::npos) << w.transfer_note;
}

TEST(ImageValues, EightBitTiffThroughTheModuleIsDecodedToo) {
  const fs::path d = temp_dir("tiff");
  const fs::path p = d / "t.tif";
  auto out = OIIO::ImageOutput::create(p.string());
  OIIO::ImageSpec spec(4, 2, 3, OIIO::TypeDesc::UINT8);
  std::vector<uint8_t> px(4 * 2 * 3, 128);
  ASSERT_TRUE(out && out->open(p.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data()));
  out->close();
  const io::FloatImage img = io::read_image(p.string(), io::ImageLimits{});
  EXPECT_NEAR(img.pixels[0], kSrgb128, 1e-6) << img.description;
  EXPECT_FALSE(img.transfer_note.empty());
}

TEST(ImageValues, RadianceCountsAreCheckedBeforeArithmetic) {
  const std::string head = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
  // 4294967312 = 2^32 + 16: read with sscanf's %d it wrapped to 16 and the picture read as 16 wide
  EXPECT_NE(
      error_of([&] { io::decode_rgbe(head + "-Y 8 +X 4294967312\n" + std::string(512, '\x40')); }).find("out of range"),
      std::string::npos);
  EXPECT_NE(error_of([&] { io::decode_rgbe(head + "-Y 8 +X 0\n"); }).find("at least 1"), std::string::npos);
  // the bound read from a header: its length and every scanline's worst encoding
  const std::string h = head + "-Y 2 +X 16\n";
  EXPECT_EQ(io::rgbe_file_bound(h), h.size() + 2u * (4u + 8u * 16u));
  EXPECT_EQ(io::rgbe_file_bound(head + "-Y 2 +X 4294967312\n"), (head + "-Y 2 +X 4294967312\n").size());
}

// A KTX1 header promising six 8192² float faces (1 GiB each) in a file of 68 bytes: refused as
// truncated before its 6 GiB are reserved (it was an "out of memory", or the allocation itself).
TEST(ImageValues, Ktx1HeadersAreCheckedAgainstTheFileBeforeAllocation) {
  std::vector<uint8_t> b = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  auto le = [&](uint32_t v) {
    for (int k = 0; k < 4; ++k) b.push_back(uint8_t(v >> (8 * k)));
  };
  le(0x04030201);
  le(0x1406);  // GL_FLOAT
  le(4);
  le(0x1908);  // GL_RGBA
  le(0x8814);  // GL_RGBA32F
  le(0x1908);
  le(8192);
  le(8192);
  le(0);
  le(0);
  le(6);
  le(1);
  le(0);
  le(uint32_t(8192u * 8192u * 16u));  // imageSize of level 0: one face
  const std::string e = error_of([&] { io::decode_ktx1(b.data(), b.size(), "big.ktx"); });
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
}

}  // namespace
}  // namespace brdfbake
