// The rendering commands (`render`, `quality`, `converge`, `compare`) from the command line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>

#include "records/csv.h"
#include "tests/cli_util.h"

namespace raycoh::test {
namespace {

TEST(CliRendering, RenderingCommandsCheckTheirInputs) {
  expect_error("render --res 0x8", "--res");
  expect_error("render --generator nope", "valid generators");
  expect_error("render --out img.tiff --res 8x8 --frames 1", "img.tiff");
  expect_error("render --crop 0,0,100,100 --res 8x8 --frames 1 --out /tmp/raycoh_crop.pfm", "--crop");
  expect_error("quality --frames 0", "--frames");
  expect_error("quality --exposure -1", "--exposure");
  expect_error("converge --time -5s", "--time");
  expect_error("converge --time 0", "--time");
  expect_error("compare /no/such.exr /no/other.exr", "/no/such.exr");
  const auto out = temp_dir("cli_render") / "r.pfm";
  const CommandResult r = run_raycoh("render --scene cornell --res 16x12 --frames 2 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(out));
}

TEST(CliRendering, QualityResumesFinishedRowsAndConvergeWritesItsSummary) {
  const auto dir = temp_dir("cli_quality");
  const auto out = dir / "q.csv";
  const std::string args =
      "quality --scenes cornell --generators noopt,ours --frames 1 --ref-frames 2 "
      "--bias-renders 2 --res 16x12 --cache " +
      (dir / "cache").string() + " --out " + out.string();
  CommandResult r = run_raycoh(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| generator | cornell |"), std::string::npos) << r.output;
  const auto complete = read_lines(out);
  ASSERT_EQ(complete.size(), 3u);
  std::filesystem::remove(out);
  write_file(out.string() + ".partial", complete[0] + "\n" + complete[1] + "\n");
  r = run_raycoh(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming: 1 rows"), std::string::npos) << r.output;
  const auto resumed = read_lines(out);
  ASSERT_EQ(resumed.size(), 3u);
  EXPECT_EQ(resumed[1], complete[1]);

  const auto conv = dir / "c.csv";
  r = run_raycoh("converge --generators noopt,ours --time 100s --max-frames 2 --ref-frames 2 --res 16x12 --cache " +
                 (dir / "cache").string() + " --out " + conv.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_lines(conv), 1 + 2 * 2);
  EXPECT_EQ(count_lines(dir / "c-summary.csv"), 1 + 3);  // ours on wall, trace and modeled_gpu
}

// A CSV file's rows as column -> text.
std::vector<std::map<std::string, std::string>> csv_rows(const std::filesystem::path& p) {
  const std::vector<std::string> lines = read_lines(p);
  std::vector<std::map<std::string, std::string>> rows;
  if (lines.empty()) return rows;
  std::vector<std::string> header;
  csv_parse_line(lines[0], header);
  for (size_t i = 1; i < lines.size(); ++i) {
    std::vector<std::string> f;
    csv_parse_line(lines[i], f);
    std::map<std::string, std::string> row;
    for (size_t c = 0; c < header.size() && c < f.size(); ++c) row[header[c]] = f[c];
    rows.push_back(row);
  }
  return rows;
}

double num(const std::map<std::string, std::string>& row, const std::string& column) {
  const auto it = row.find(column);
  EXPECT_NE(it, row.end()) << column;
  return it == row.end() || it->second.empty() ? std::nan("") : std::stod(it->second);
}

// Issue 12: converge's curve and summary carry the reference's noise (a 128-frame reference has two 64-frame
// halves) with quality's definitions: rel_mse_corr = rel_mse - ref_noise_rel_mse, the share, and the summary's
// corrected errors and equal-time ratio.
TEST(CliRendering, ConvergeReportsTheReferenceNoise) {
  const auto dir = temp_dir("cli_converge_noise");
  const auto conv = dir / "c.csv";
  const CommandResult r = run_raycoh(
      "converge --generators noopt,ours --time 100s --max-frames 3 --ref-frames 128 --res 24x16 "
      "--gpu-model none --cache " +
      (dir / "cache").string() + " --out " + conv.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("reference noise: MSE"), std::string::npos) << r.output;
  const auto rows = csv_rows(conv);
  ASSERT_EQ(rows.size(), 6u);
  const double noise = num(rows[0], "ref_noise_rel_mse");
  EXPECT_GT(noise, 0);
  for (const auto& row : rows) {
    EXPECT_EQ(num(row, "ref_noise_rel_mse"), noise);
    // The CSV holds 6 significant digits.
    EXPECT_NEAR(num(row, "rel_mse_corr"), std::max(0.0, num(row, "rel_mse") - noise), 1e-5 * num(row, "rel_mse"));
    EXPECT_GE(num(row, "ref_noise_share"), noise / num(row, "rel_mse") * (1 - 1e-5));
    EXPECT_LE(num(row, "mse_corr"), num(row, "mse"));
    EXPECT_GE(num(row, "psnr_corr"), num(row, "psnr") - 1e-9);
  }
  const auto summary = csv_rows(dir / "c-summary.csv");
  ASSERT_EQ(summary.size(), 2u);  // ours on wall and trace
  for (const auto& row : summary) {
    EXPECT_EQ(num(row, "ref_noise_rel_mse"), noise);
    if (row.at("error").empty() || row.at("baseline_error").empty()) {
      // One curve has no point at the horizon on this clock (on a loaded machine a first frame can take longer
      // than all frames of the other): the corrected figures are as undefined as the raw ones.
      if (row.at("error").empty()) {
        EXPECT_EQ(row.at("error_corr"), "");
      }
      if (row.at("baseline_error").empty()) {
        EXPECT_EQ(row.at("baseline_error_corr"), "");
      }
      EXPECT_EQ(row.at("equal_time_error_ratio_corr"), "");
      continue;
    }
    const double e = num(row, "error") - noise, b = num(row, "baseline_error") - noise;
    EXPECT_NEAR(num(row, "error_corr"), e, 1e-5 * num(row, "error"));
    EXPECT_NEAR(num(row, "baseline_error_corr"), b, 1e-5 * num(row, "baseline_error"));
    EXPECT_NEAR(num(row, "equal_time_error_ratio_corr"), e / b, 1e-4 * e / b);
    EXPECT_NEAR(num(row, "ref_noise_share"), noise / std::min(num(row, "error"), num(row, "baseline_error")), 1e-5);
  }
}

// A --reference file that is a cache entry carries its frame count (its sidecar): quality and converge record it,
// an explicit --ref-frames that contradicts it is refused, and a bare file (no sidecar) leaves it unknown. quality's
// residual noise share (the noise estimate's standard error) is below the noise share itself.
TEST(CliRendering, ReferenceFilesCarryTheirFrameCount) {
  namespace fs = std::filesystem;
  const auto dir = temp_dir("cli_reference_frames");
  const CommandResult made =
      run_raycoh("reference --scene cornell --res 24x16 --frames 128 --cache " + (dir / "cache").string());
  ASSERT_EQ(made.exit_code, 0) << made.output;
  fs::path entry;
  for (const auto& e : fs::directory_iterator(dir / "cache"))
    if (e.path().extension() == ".exr" && e.path().stem().string().find("-half1") == std::string::npos)
      entry = e.path();
  ASSERT_FALSE(entry.empty());
  const std::string conv = "converge --generators noopt,ours --time 100s --max-frames 2 --res 24x16 --gpu-model none ";
  const CommandResult c = run_raycoh(conv + "--reference " + entry.string() + " --out " + (dir / "c.csv").string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("reference 128 frames (file)"), std::string::npos) << c.output;
  EXPECT_EQ(csv_rows(dir / "c.csv").at(0).at("ref_frames"), "128");
  expect_error(conv + "--ref-frames 512 --reference " + entry.string() + " --out " + (dir / "x.csv").string(),
               "holds 128 frames");
  const CommandResult q = run_raycoh(
      "quality --scenes cornell --generators noopt --frames 2 --bias-renders 2 "
      "--res 24x16 --reference " +
      entry.string() + " --out " + (dir / "q.csv").string());
  ASSERT_EQ(q.exit_code, 0) << q.output;
  const auto row = csv_rows(dir / "q.csv").at(0);
  EXPECT_EQ(row.at("ref_frames"), "128");
  EXPECT_GT(num(row, "ref_noise_residual_share"), 0);
  EXPECT_LT(num(row, "ref_noise_residual_share"), num(row, "ref_noise_share"));
  // The same image without its sidecar: the count is unknown.
  fs::create_directories(dir / "bare");
  fs::copy_file(entry, dir / "bare" / "ref.exr");
  const CommandResult b =
      run_raycoh(conv + "--reference " + (dir / "bare" / "ref.exr").string() + " --out " + (dir / "b.csv").string());
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_NE(b.output.find("reference of unknown frames (file)"), std::string::npos) << b.output;
  EXPECT_EQ(csv_rows(dir / "b.csv").at(0).at("ref_frames"), "");
}

// Issue 12: quality's hybrid_diffuse_share (0 for NoOpt, which has no groups; cornell's hybrid groups give ours a
// share) and HDR-FLIP through the flip program: a stand-in flip ($RAYCOH_FLIP) that answers LDR calls (PNG) with
// one mean and HDR calls with the exposure range and a mean per test image, which must be the linear renders as
// EXR files (one per render) against an EXR reference; flip_hdr is their mean.
TEST(CliRendering, QualityReportsHybridShareAndHdrFlip) {
  const auto dir = temp_dir("cli_quality_flip");
  const auto fake = dir / "flip";
  write_file(
      fake,
      "#!/bin/sh\n"
      "case \"$*\" in\n"
      "  *.png*) echo '     Mean: 0.25' ;;\n"
      "  *) n=0; for a in \"$@\"; do case \"$a\" in *.exr) test -s \"$a\" || exit 1; n=$((n+1));; esac; done\n"
      "     test $n -eq 3 || exit 1\n"
      "     echo '     Start exposure: -1.5'; echo '     Stop exposure: 2.25'; echo '     Number of exposures: 4'\n"
      "     echo '     Mean: 0.1'; echo '     Weighted median: 0.9'; echo '     Mean: 0.3' ;;\n"
      "esac\n");
  std::filesystem::permissions(fake, std::filesystem::perms::owner_all);
  const auto out = dir / "q.csv";
  const CommandResult r = run_shell("RAYCOH_FLIP=" + fake.string() +
                                    " $R quality --scenes cornell --generators noopt,ours --frames 2 --ref-frames 2 "
                                    "--bias-renders 2 --res 32x24 --cache " +
                                    (dir / "cache").string() + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = csv_rows(out);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(num(rows[0], "hybrid_diffuse_share"), 0.0);
  EXPECT_GT(num(rows[1], "hybrid_diffuse_share"), 0.02);
  EXPECT_LT(num(rows[1], "hybrid_diffuse_share"), 0.5);
  for (const auto& row : rows) {
    EXPECT_EQ(num(row, "flip"), 0.25);
    EXPECT_NEAR(num(row, "flip_hdr"), 0.2, 1e-12);
    EXPECT_EQ(row.at("flip_hdr_exposure"), "-1.5..2.25/4");
  }
  // raycoh report shows them per scene and method.
  const CommandResult rep = run_raycoh("report " + out.string() + " --out " + (dir / "report.html").string());
  ASSERT_EQ(rep.exit_code, 0) << rep.output;
  std::ifstream md(dir / "report.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("### Bias and the hybrid rule's exposure"), std::string::npos) << text;
  EXPECT_NE(text.find("| cornell | noopt | 0.0% |"), std::string::npos) << text;
  EXPECT_NE(text.find("| 0.2500 | 0.2000 |"), std::string::npos) << text;
}

// Issue 32, --denoise oidn through a stand-in oidnDenoise ($RAYCOH_OIDN) that checks its auxiliary inputs and
// returns the colour unchanged: every denoised figure then equals the raw one, quality writes the denoised image,
// the albedo and the normal of render 0, converge fills its denoised columns at frames 1, 2, 4, ... only, and a
// quality run of another --denoise is refused on resume naming the column.
TEST(CliRendering, DenoiseFillsTheDenoisedColumnsThroughTheProgram) {
  const auto dir = temp_dir("cli_denoise");
  const auto fake = dir / "oidnDenoise";
  write_file(fake,
             "#!/bin/sh\n"
             "while [ $# -gt 0 ]; do case \"$1\" in --hdr) c=$2;; --alb) a=$2;; --nrm) n=$2;; -o) o=$2;; esac; "
             "shift 2; done\n"
             "test -s \"$a\" && test -s \"$n\" && cp \"$c\" \"$o\"\n");
  std::filesystem::permissions(fake, std::filesystem::perms::owner_all);
  const auto out = dir / "q.csv";
  const std::string quality = "RAYCOH_OIDN=" + fake.string() +
                              " $R quality --scenes cornell --generators noopt,ours:k=4 --frames 2 --ref-frames 2 "
                              "--bias-renders 2 --res 32x24 --cache " +
                              (dir / "cache").string() + " --images " + (dir / "quality-images").string() + " --out " +
                              out.string();
  CommandResult r = run_shell(quality + " --denoise oidn");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| cornell | ours:k=4 |"), std::string::npos) << r.output;
  for (const auto& row : csv_rows(out)) {
    EXPECT_EQ(row.at("denoise"), "oidn");
    for (const char* c : {"psnr", "psnr_std", "ssim", "rmse", "rel_mse", "mse", "rel_mse_ds8"})
      EXPECT_EQ(row.at(std::string("denoised_") + c), row.at(c)) << c;
    EXPECT_GE(num(row, "denoise_s"), 0.0);
  }
  for (const char* f : {"cornell-ours_k_4-denoised.png", "cornell-ours_k_4-albedo.exr", "cornell-ours_k_4-normal.exr"})
    EXPECT_TRUE(std::filesystem::exists(dir / "quality-images" / f)) << f;
  // raycoh report puts the denoised images, crops and error maps beside the raw ones (files named as quality names
  // them: ours_k_4 for ours:k=4).
  const CommandResult rep = run_raycoh("report " + out.string() + " --out " + (dir / "report.html").string());
  ASSERT_EQ(rep.exit_code, 0) << rep.output;
  std::ifstream html(dir / "report.html");
  const std::string page((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  for (const char* alt :
       {"cornell ours:k=4 error map", "cornell ours:k=4-denoised error map", "cornell ours:k=4-denoised crop"})
    EXPECT_NE(page.find(alt), std::string::npos) << alt;
  r = run_shell(quality + " --denoise none");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("denoise"), std::string::npos) << r.output;

  const auto conv = dir / "c.csv";
  r = run_shell("RAYCOH_OIDN=" + fake.string() +
                " $R converge --generators noopt,ours --time 100s --max-frames 3 --ref-frames 2 --res 16x12 "
                "--gpu-model none --denoise oidn --cache " +
                (dir / "cache").string() + " --out " + conv.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = csv_rows(conv);
  ASSERT_EQ(rows.size(), 6u);
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("denoise"), "oidn");
    if (row.at("frame") == "3") {
      EXPECT_EQ(row.at("denoised_rel_mse"), "");
    } else {
      EXPECT_EQ(row.at("denoised_rel_mse"), row.at("rel_mse"));
      EXPECT_EQ(row.at("denoised_psnr"), row.at("psnr"));
    }
  }
}

// Without an oidnDenoise (no $RAYCOH_OIDN, no .venv in the working folder) one line says so and the denoised
// columns stay empty; an unknown denoiser is a one-line error naming the valid ones.
TEST(CliRendering, DenoiseWithoutOidnSaysSoOnceAndLeavesTheColumnsEmpty) {
  expect_error("quality --denoise optix", "none, oidn");
  expect_error("converge --denoise optix", "none, oidn");
  const auto dir = temp_dir("cli_denoise_missing");
  const std::string cd = "cd " + dir.string() + " && RAYCOH_OIDN= $R ";
  CommandResult r =
      run_shell(cd + "quality --scenes cornell --generators noopt --frames 1 --ref-frames 2 --res 16x12 " +
                "--cache cache --out q.csv --denoise oidn");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r.output += run_shell(cd + "converge --generators noopt --time 100s --max-frames 1 --ref-frames 2 --res 16x12 " +
                        "--gpu-model none --cache cache --out c.csv --denoise oidn")
                  .output;
  size_t lines = 0;
  for (size_t at = 0; (at = r.output.find("OIDN: not available", at)) != std::string::npos; ++at) ++lines;
  EXPECT_EQ(lines, 2u) << r.output;  // once per command
  for (const char* csv : {"q.csv", "c.csv"})
    for (const auto& row : csv_rows(dir / csv)) {
      EXPECT_EQ(row.at("denoise"), "oidn") << csv;
      EXPECT_EQ(row.at("denoised_rel_mse"), "") << csv;
      EXPECT_EQ(row.at("denoised_psnr"), "") << csv;
    }
  EXPECT_FALSE(std::filesystem::exists(dir / "q-images" / "cornell-noopt-denoised.png"));
}

}  // namespace
}  // namespace raycoh::test
