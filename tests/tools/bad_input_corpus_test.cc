// The bad-input corpus: every row writes one malformed input (generated here, nothing is
// stored), runs the real `omnidso` executable on it as a user would, under a time limit,
// and asserts the contract of docs/architecture.md ("What the readers accept"): exit status
// 2, exactly one line on stderr, "omnidso: error: ..." naming the file (and line where the
// format has lines) or the option, and the case's directory byte for byte as before — no
// --out created or partly written, no file overwritten, no staging directory left behind.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <omnidso/cli/process_pool.hpp>

#include "bad_input_fixtures.hpp"

namespace omnidso {
namespace {
namespace fs = std::filesystem;
using test::BadInputFixtures;

// One row: what to write into the case's directory, the command line (after `omnidso`), and
// what the one error line must contain. "{dir}" stands for the case's directory.
struct BadInputCase {
  std::string name;
  std::function<void(const BadInputFixtures& fixtures, const fs::path& dir)> write;
  std::string arguments;
  std::string expected;
};

// Every file, directory and symbolic link under `root` with its content or target, so that
// any change a run makes — a new --out, a rewritten file, a left-over staging directory —
// shows as a difference.
std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> entries;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator();
       ++it) {
    const fs::path& path = it->path();
    const std::string key = path.lexically_relative(root).string();
    if (it->is_symlink()) {
      entries[key] = "-> " + fs::read_symlink(path).string();
    } else if (it->is_directory()) {
      entries[key] = "dir";
    } else {
      entries[key] = test::readBytes(path);
    }
  }
  return entries;
}

std::string replaceDir(std::string text, const std::string& dir) {
  for (size_t at = text.find("{dir}"); at != std::string::npos; at = text.find("{dir}", at)) {
    text.replace(at, 5, dir);
  }
  return text;
}

// Splits on spaces; an argument "''" is the empty string (the empty-value cases).
std::vector<std::string> splitArguments(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string word; in >> word;) out.push_back(word == "''" ? "" : word);
  return out;
}

// Runs every case of `table` (two at a time) and checks the contract for each.
void expectCleanRefusals(const std::vector<BadInputCase>& table) {
  const BadInputFixtures& fixtures = BadInputFixtures::get();
  const fs::path root = fixtures.caseRoot(::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::vector<cli::ProcessSpec> specs;
  std::vector<std::map<std::string, std::string>> before;
  for (const BadInputCase& c : table) {
    const fs::path dir = root / c.name;
    fs::create_directories(dir);
    c.write(fixtures, dir);
    cli::ProcessSpec spec;
    spec.argv = {OMNIDSO_EXECUTABLE};
    for (const std::string& a : splitArguments(replaceDir(c.arguments, dir.string()))) {
      spec.argv.push_back(a);
    }
    spec.log_path = (root / (c.name + ".log")).string();
    spec.timeout_s = 60;  // a hang is a failure, never a stuck test suite
    specs.push_back(spec);
    before.push_back(snapshot(dir));
  }
  const std::vector<cli::ProcessOutcome> outcomes = cli::runProcesses(specs, 2);
  for (size_t i = 0; i < table.size(); ++i) {
    const BadInputCase& c = table[i];
    const fs::path dir = root / c.name;
    SCOPED_TRACE(c.name + ": omnidso " + replaceDir(c.arguments, dir.string()));
    const std::string log = test::readBytes(specs[i].log_path);
    EXPECT_EQ(outcomes[i].kind, cli::ProcessOutcome::Kind::kExited) << outcomes[i].describe();
    EXPECT_EQ(outcomes[i].exit_code, 2) << log;
    // One line: "omnidso: error: " and the message, naming the file or option.
    EXPECT_EQ(log.rfind("omnidso: error: ", 0), 0u) << log;
    EXPECT_TRUE(!log.empty() && log.find('\n') == log.size() - 1) << "not one line:\n" << log;
    const std::string expected = replaceDir(c.expected, dir.string());
    EXPECT_NE(log.find(expected), std::string::npos) << "expected '" << expected << "' in\n" << log;
    EXPECT_EQ(snapshot(dir), before[i]) << "the case's files changed";
  }
}

// Writers of the rows: a file with given content, a copy of a fixture dataset with one file
// replaced, binary garbage.
auto file(const std::string& name, const std::string& content) {
  return [=](const BadInputFixtures&, const fs::path& dir) { test::writeBytes(dir / name, content); };
}
auto tumWith(const std::string& name, const std::string& content) {
  return [=](const BadInputFixtures& f, const fs::path& dir) {
    f.copyTumDataset(dir / "ds");
    test::writeBytes(dir / "ds" / name, content);
  };
}
auto aslWith(const std::string& name, const std::string& content) {
  return [=](const BadInputFixtures& f, const fs::path& dir) {
    f.copyAslDataset(dir / "ds");
    test::writeBytes(dir / "ds" / name, content);
  };
}
const std::string kRun = "run {dir}/ds --out {dir}/out --quiet";
const std::string kEval = "eval --gt {dir}/gt.txt --est {dir}/gt.txt";
const std::string kTumPose = "1 0 0 0 0 0 0 1\n";

TEST(BadInputCorpus, Trajectories) {
  const std::string ok = "# t tx ty tz qx qy qz qw\n" + kTumPose;
  expectCleanRefusals({
      {"truncated_line", file("gt.txt", ok + "2 0 0\n"), kEval, "{dir}/gt.txt:3: "},
      {"text_in_number", file("gt.txt", ok + "2 0 0x1 0 0 0 0 1\n"), kEval, "{dir}/gt.txt:3: "},
      {"quaternion_norm_zero", file("gt.txt", ok + "2 0 0 0 0 0 0 0\n"), kEval, "{dir}/gt.txt:3: "},
      {"nan_position", file("gt.txt", ok + "2 nan 0 0 0 0 0 1\n"), kEval, "{dir}/gt.txt:3: "},
      {"inf_timestamp", file("gt.txt", ok + "inf 0 0 0 0 0 0 1\n"), kEval, "{dir}/gt.txt:3: "},
      {"huge_number", file("gt.txt", ok + "2 1e400 0 0 0 0 0 1\n"), kEval, "{dir}/gt.txt:3: "},
      {"only_comments", file("gt.txt", "# nothing\n\n"), kEval, "{dir}/gt.txt: "},
      {"garbage_tum", file("gt.txt", test::garbage(1)), kEval, "{dir}/gt.txt:"},
      {"garbage_kitti", file("gt.txt", test::garbage(2)), kEval + " --format kitti",
       "{dir}/gt.txt:"},
      {"garbage_euroc", file("gt.txt", test::garbage(3)), kEval + " --format euroc",
       "{dir}/gt.txt:"},
      {"kitti_not_rotation", file("gt.txt", "1 0 0 0 0 1 0 0 0 0 3 0\n"), kEval + " --format kitti",
       "{dir}/gt.txt:1: "},
      {"euroc_text_stamp", file("gt.txt", "12a4,0,0,0,1,0,0,0\n"), kEval + " --format euroc",
       "{dir}/gt.txt:1: "},
      {"strict_repeated_stamp", file("gt.txt", ok + kTumPose), kEval + " --strict",
       "{dir}/gt.txt:3: "},
      {"strict_unsorted", file("gt.txt", ok + "0.5 0 0 0 0 0 0 1\n"), kEval + " --strict",
       "{dir}/gt.txt:3: "},
  });
}

TEST(BadInputCorpus, Calibrations) {
  const std::string kalibr = "cam0:\n  camera_model: omni\n  distortion_model: none\n";
  const auto omni = [&](const std::string& intrinsics, const std::string& resolution) {
    return file("cam.yaml", kalibr + "  intrinsics: " + intrinsics + "\n  resolution: " +
                                resolution + "\n");
  };
  const std::string good = "[1.0, 30, 30, 47.5, 47.5]";
  const std::string info = "camera info {dir}/cam.yaml";
  const std::string txt = "camera info {dir}/camera.txt";
  expectCleanRefusals({
      {"kalibr_missing_intrinsics", file("cam.yaml", kalibr + "  resolution: [96, 96]\n"), info,
       "{dir}/cam.yaml: field 'cam0.intrinsics'"},
      {"kalibr_wrong_count", omni("[30, 30, 47.5, 47.5]", "[96, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.intrinsics'"},
      {"kalibr_nan", omni("[1.0, .nan, 30, 47.5, 47.5]", "[96, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.intrinsics'"},
      {"kalibr_inf", omni("[1.0, 30, .inf, 47.5, 47.5]", "[96, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.intrinsics'"},
      {"kalibr_negative_focal", omni("[1.0, -30, 30, 47.5, 47.5]", "[96, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.intrinsics'"},
      {"kalibr_zero_focal", omni("[1.0, 30, 0, 47.5, 47.5]", "[96, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.intrinsics'"},
      {"kalibr_xi_negative", omni("[-0.5, 30, 30, 47.5, 47.5]", "[96, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.intrinsics'"},
      {"kalibr_ds_alpha_above_one",
       file("cam.yaml", "camera_model: ds\nintrinsics: [0.1, 1.5, 30, 30, 47.5, 47.5]\n"
                        "resolution: [96, 96]\n"),
       info, "{dir}/cam.yaml: field 'intrinsics'"},
      {"kalibr_resolution_zero", omni(good, "[0, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.resolution'"},
      {"kalibr_resolution_huge", omni(good, "[1e12, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.resolution'"},
      {"kalibr_focal_huge", omni("[1.0, 1e300, 1e300, 47.5, 47.5]", "[96, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.intrinsics'"},
      {"kalibr_text_in_number", omni("[1.0, 30, 3O, 47.5, 47.5]", "[96, 96]"), info,
       "{dir}/cam.yaml: field 'cam0.intrinsics'"},
      {"kalibr_bad_yaml", file("cam.yaml", "cam0:\n  camera_model: [omni\n  x: 1\n"), info,
       "{dir}/cam.yaml:"},
      {"kalibr_garbage", file("cam.yaml", test::garbage(4)), info, "{dir}/cam.yaml"},
      {"euroc_sensor_tbs_scalar",
       file("cam.yaml", "camera_model: pinhole\nintrinsics: [30, 30, 47.5, 47.5]\n"
                        "distortion_model: radial-tangential\ndistortion_coefficients: [0, 0, 0, 0]\n"
                        "resolution: [96, 96]\nT_BS: 5\n"),
       info, "{dir}/cam.yaml: field 'T_BS'"},
      {"dso_missing_size_line", file("camera.txt", "UCM 30 30 47.5 47.5 1.0\n"), txt,
       "{dir}/camera.txt: "},
      {"dso_wrong_count", file("camera.txt", "UCM 30 30 47.5 47.5\n96 96\n"), txt,
       "{dir}/camera.txt:1: "},
      {"dso_nan", file("camera.txt", "UCM nan 30 47.5 47.5 1.0\n96 96\n"), txt,
       "{dir}/camera.txt:1: "},
      {"dso_inf", file("camera.txt", "UCM 30 30 47.5 inf 1.0\n96 96\n"), txt,
       "{dir}/camera.txt:1: "},
      {"dso_negative_focal", file("camera.txt", "UCM -30 30 47.5 47.5 1.0\n96 96\n"), txt,
       "{dir}/camera.txt:1: "},
      {"dso_xi_negative", file("camera.txt", "UCM 30 30 47.5 47.5 -2\n96 96\n"), txt,
       "{dir}/camera.txt:1: "},
      {"dso_resolution_zero", file("camera.txt", "UCM 30 30 47.5 47.5 1.0\n0 96\n"), txt,
       "{dir}/camera.txt:2: "},
      {"dso_resolution_huge", file("camera.txt", "UCM 30 30 47.5 47.5 1.0\n99999999999 96\n"),
       txt, "{dir}/camera.txt:2: "},
      {"dso_garbage", file("camera.txt", test::garbage(5)), txt, "{dir}/camera.txt"},
  });
}

TEST(BadInputCorpus, PhotometricCalibration) {
  std::string decreasing;
  for (int k = 0; k < 256; ++k) decreasing += std::to_string(255 - k) + " ";
  std::string with_nan;
  for (int k = 0; k < 256; ++k) with_nan += (k == 7 ? std::string("nan") : std::to_string(k)) + " ";
  expectCleanRefusals({
      {"pcalib_three_values", tumWith("pcalib.txt", "0 1 2\n"), kRun, "{dir}/ds/pcalib.txt:1: "},
      {"pcalib_decreasing", tumWith("pcalib.txt", decreasing + "\n"), kRun,
       "{dir}/ds/pcalib.txt:1: "},
      {"pcalib_nan", tumWith("pcalib.txt", with_nan + "\n"), kRun, "{dir}/ds/pcalib.txt:1: "},
      {"pcalib_garbage", tumWith("pcalib.txt", test::garbage(6)), kRun, "{dir}/ds/pcalib.txt"},
      {"vignette_wrong_size",
       [](const BadInputFixtures& f, const fs::path& dir) {
         f.copyTumDataset(dir / "ds");
         test::writeGreyPng(dir / "ds" / "vignette.png", 10, 10, 200);
       },
       kRun, "{dir}/ds/vignette.png"},
      {"vignette_all_zero",
       [](const BadInputFixtures& f, const fs::path& dir) {
         f.copyTumDataset(dir / "ds");
         test::writeGreyPng(dir / "ds" / "vignette.png", 96, 96, 0);
       },
       kRun, "{dir}/ds/vignette.png"},
      {"vignette_garbage", tumWith("vignette.png", test::garbage(7)), kRun,
       "{dir}/ds/vignette.png"},
  });
}

TEST(BadInputCorpus, Datasets) {
  expectCleanRefusals({
      {"tum_text_timestamp", tumWith("times.txt", "00000 1.0\n00001 1.0x5\n"), kRun,
       "{dir}/ds/times.txt:2: "},
      {"tum_negative_exposure", tumWith("times.txt", "00000 1.0 -3\n"), kRun,
       "{dir}/ds/times.txt:1: "},
      {"tum_time_going_back", tumWith("times.txt", "00000 1.0\n00001 0.9\n00002 1.1\n"), kRun,
       "{dir}/ds/times.txt:2: "},
      {"tum_images_missing_at_end", tumWith("times.txt", "00000 1\n00001 1.05\n00002 1.1\n"
                                                         "00003 1.15\n00004 1.2\n"),
       kRun, "{dir}/ds/times.txt:4: 2 listed images not found at the end"},
      {"tum_times_garbage", tumWith("times.txt", test::garbage(8)), kRun, "{dir}/ds/times.txt"},
      {"tum_corrupt_second_image", tumWith("images/00001.png", test::garbage(9)), kRun,
       "{dir}/ds/times.txt:3: "},
      {"tum_groundtruth_truncated", tumWith("groundtruth.txt", "0 0 0 0 0 0 0 1\n0.05 0 0\n"),
       kRun, "{dir}/ds/groundtruth.txt:2: "},
      {"tum_groundtruth_garbage", tumWith("groundtruth.txt", test::garbage(10)), kRun,
       "{dir}/ds/groundtruth.txt"},
      {"tum_camchain_garbage", tumWith("camchain.yaml", test::garbage(11)), kRun,
       "{dir}/ds/camchain.yaml"},
      {"tum_calibration_other_size",
       tumWith("camchain.yaml", "cam0:\n  camera_model: omni\n  intrinsics: [1, 30, 30, 63.5, "
                                "47.5]\n  resolution: [128, 96]\n"),
       kRun, "{dir}/ds/camchain.yaml: calibration is for 128x96 images"},
      {"tum_empty_folder", [](const BadInputFixtures&, const fs::path& dir) {
         fs::create_directories(dir / "ds");
       }, kRun, "{dir}/ds: not a dataset"},
      {"asl_text_timestamp", aslWith("mav0/cam0/data.csv", "#t,f\n12x,a.png\n"), kRun,
       "{dir}/ds/mav0/cam0/data.csv:2: "},
      {"asl_three_fields", aslWith("mav0/cam0/data.csv", "1000000000,1.png,3\n"), kRun,
       "{dir}/ds/mav0/cam0/data.csv:1: "},
      {"asl_image_missing",
       aslWith("mav0/cam0/data.csv", "1000000000,1000000000.png\n1050000000,1050000000.png\n"
                                     "1100000000,1100000000.png\n1150000000,gone.png\n"),
       kRun, "{dir}/ds/mav0/cam0/data.csv:4: image '"},
      {"asl_csv_garbage", aslWith("mav0/cam0/data.csv", test::garbage(12)), kRun,
       "{dir}/ds/mav0/cam0/data.csv"},
      {"asl_sensor_garbage", aslWith("mav0/cam0/sensor.yaml", test::garbage(13)), kRun,
       "{dir}/ds/mav0/cam0/sensor.yaml"},
  });
}

TEST(BadInputCorpus, ConfigFiles) {
  const auto config = [](const std::string& content) {
    return [=](const BadInputFixtures& f, const fs::path& dir) {
      f.copyTumDataset(dir / "ds");
      test::writeBytes(dir / "config.yaml", content);
    };
  };
  const std::string run = kRun + " --config {dir}/config.yaml";
  expectCleanRefusals({
      {"config_unknown_key", config("window:\n  max_iterations: 3\n  colour: blue\n"), run,
       "{dir}/config.yaml:3: "},
      {"config_wrong_type", config("window.max_iterations: three\n"), run, "{dir}/config.yaml:1: "},
      {"config_list_value", config("pyramid_levels: [1, 2]\n"), run, "{dir}/config.yaml:1: "},
      {"config_negative_count", config("pyramid_levels: -2\n"), run, "{dir}/config.yaml:1: "},
      {"config_nan", config("tracker.huber_threshold: .nan\n"), run, "{dir}/config.yaml:1: "},
      {"config_key_is_a_list", config("? [a, b]\n: 1\n"), run, "{dir}/config.yaml:1: "},
      {"config_bad_yaml", config("window:\n  max_iterations: [3\n"), run, "{dir}/config.yaml:"},
      {"config_garbage", config(test::garbage(14)), run, "{dir}/config.yaml"},
  });
}

TEST(BadInputCorpus, CommandLineValues) {
  const auto dataset = [](const BadInputFixtures& f, const fs::path& dir) {
    f.copyTumDataset(dir / "ds");
  };
  const auto dataset_and_file = [](const BadInputFixtures& f, const fs::path& dir) {
    f.copyTumDataset(dir / "ds");
    test::writeBytes(dir / "out", "the user's file\n");
  };
  expectCleanRefusals({
      {"negative_keyframes", dataset, kRun + " --keyframes -3", "--keyframes"},
      {"zero_points", dataset, kRun + " --points 0", "--points"},
      {"negative_max_frames", dataset, kRun + " --max-frames -1", "--max-frames"},
      {"text_seed", dataset, kRun + " --seed abc", "--seed"},
      {"empty_out", dataset, "run {dir}/ds --out '' --quiet", "--out"},
      {"empty_dataset", dataset, "run '' --out {dir}/out --quiet", "DATASET: empty path"},
      {"empty_camera_model", dataset, kRun + " --camera-model ''", "--camera-model"},
      {"empty_setting", dataset, kRun + " --set ''", "--set"},
      {"setting_without_value", dataset, kRun + " --set window.max_iterations=", "window.max_iterations"},
      {"empty_calib", dataset, kRun + " --calib ''", "--calib"},
      {"out_is_a_file", dataset_and_file, kRun, "{dir}/out: exists and is not a directory"},
      {"eval_zero_delta", file("gt.txt", kTumPose), kEval + " --delta 0", "--delta"},
      {"eval_negative_max_dt", file("gt.txt", kTumPose), kEval + " --max-dt -1", "--max-dt"},
      {"synth_negative_frames", file("keep.txt", "x"), "synth --frames -5 --out {dir}/s --quiet",
       "--frames"},
      {"synth_zero_size", file("keep.txt", "x"), "synth --size 0x48 --out {dir}/s --quiet",
       "--size"},
      {"synth_huge_size", file("keep.txt", "x"),
       "synth --size 100000x100000 --out {dir}/s --quiet", "--size"},
  });
}

// Symbolic links that point at themselves, where a file or a directory is expected.
TEST(BadInputCorpus, SymlinkLoops) {
  const auto loop = [](const std::string& name) {
    return [=](const BadInputFixtures& f, const fs::path& dir) {
      f.copyTumDataset(dir / "ds");
      fs::remove_all(dir / "ds" / name);
      fs::create_symlink(name.substr(name.rfind('/') + 1), dir / "ds" / name);
    };
  };
  expectCleanRefusals({
      {"loop_times", loop("times.txt"), kRun, "{dir}/ds/times.txt"},
      {"loop_images_dir", loop("images"), kRun, "{dir}/ds/images"},
      {"loop_image", loop("images/00001.png"), kRun, "{dir}/ds/times.txt:3: "},
      {"loop_camchain", loop("camchain.yaml"), kRun, "{dir}/ds/camchain.yaml"},
      {"loop_groundtruth", loop("groundtruth.txt"), kRun, "{dir}/ds/groundtruth.txt"},
      {"loop_trajectory",
       [](const BadInputFixtures&, const fs::path& dir) { fs::create_symlink("gt.txt", dir / "gt.txt"); },
       kEval, "{dir}/gt.txt"},
  });
}

// Unreadable files: mode 000. Root reads them anyway (CAP_DAC_OVERRIDE), so there the test
// cannot make an unreadable file and says so instead of passing without checking.
TEST(BadInputCorpus, UnreadableFiles) {
  const test::BadInputFixtures& fixtures = BadInputFixtures::get();
  const fs::path probe = fixtures.caseRoot("permission_probe") / "probe";
  test::writeBytes(probe, "x");
  fs::permissions(probe, fs::perms::none);
  const bool permissions_bypassed = ::access(probe.c_str(), R_OK) == 0;
  if (permissions_bypassed) {
    GTEST_SKIP() << "running as root (uid " << ::geteuid()
                 << "): mode 000 does not stop reading, so unreadable files cannot be made here";
  }
  const auto unreadable = [](const std::string& name) {
    return [=](const BadInputFixtures& f, const fs::path& dir) {
      f.copyTumDataset(dir / "ds");
      fs::permissions(dir / "ds" / name, fs::perms::none);
    };
  };
  expectCleanRefusals({
      {"unreadable_times", unreadable("times.txt"), kRun, "{dir}/ds/times.txt"},
      {"unreadable_camchain", unreadable("camchain.yaml"), kRun, "{dir}/ds/camchain.yaml"},
      {"unreadable_pcalib", unreadable("pcalib.txt"), kRun, "{dir}/ds/pcalib.txt"},
      {"unreadable_image", unreadable("images/00001.png"), kRun, "{dir}/ds/times.txt:3: "},
  });
}

}  // namespace
}  // namespace omnidso
