// The CSV layer of the harness: escaping, the column schemas (round trip, damaged values, resume keys), and
// write errors.
#include "records/csv.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "harness/common/exit_codes.h"
#include "records/experiment_row.h"
#include "records/hw_columns.h"
#include "records/quality_row.h"
#include "records/record_csv.h"
#include "tests/cli_util.h"

namespace raycoh::test {
namespace {

TEST(Csv, EscapesAndParsesQuotedFields) {
  EXPECT_EQ(csv_escape("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_escape("say \"hi\""), "\"say \"\"hi\"\"\"");
  std::vector<std::string> fields;
  ASSERT_TRUE(csv_parse_line("x,\"a,b\",\"q\"\"q\",", fields));
  EXPECT_EQ(fields, (std::vector<std::string>{"x", "a,b", "q\"q", ""}));
  EXPECT_FALSE(csv_parse_line("\"open", fields));
}

// The experiment CSV's columns before the recorded ones, in file order.
const std::vector<std::string> kExperimentColumns = {"scene",
                                                     "scene_triangles",
                                                     "pass",
                                                     "method",
                                                     "generator",
                                                     "generator_params",
                                                     "tracer",
                                                     "tracer_params",
                                                     "bvh",
                                                     "width",
                                                     "height",
                                                     "frame",
                                                     "seed",
                                                     "rays",
                                                     "gen_ms",
                                                     "trace_ms",
                                                     "trace_ms_min",
                                                     "repeats",
                                                     "mray_s",
                                                     "below_geometric",
                                                     "below_shading",
                                                     "non_finite",
                                                     "groups_diffuse",
                                                     "groups_glossy",
                                                     "groups_hybrid",
                                                     "groups_independent",
                                                     "groups_world",
                                                     "hybrid_mean_fallback",
                                                     "reused_rays",
                                                     "encoder",
                                                     "encoder_params",
                                                     "permute",
                                                     "key_ms",
                                                     "sort_ms",
                                                     "permute_ms",
                                                     "e2e_ms",
                                                     "e2e_mray_s",
                                                     "simt_efficiency",
                                                     "node_simt_efficiency",
                                                     "lines_per_ray",
                                                     "fetches_per_ray",
                                                     "l1_misses_per_ray",
                                                     "l2_misses_per_ray",
                                                     "dram_bytes_per_ray",
                                                     "modeled_ms",
                                                     "modeled_mray_s",
                                                     "modeled_e2e_ms",
                                                     "modeled_e2e_mray_s",
                                                     "modeled_limiter",
                                                     "modeled_l1_wavefronts_per_ray",
                                                     "modeled_l1_local_wavefronts_per_ray",
                                                     "modeled_gen_ms",
                                                     "modeled_key_ms",
                                                     "modeled_sort_ms",
                                                     "modeled_permute_ms",
                                                     "modeled_gen_bytes",
                                                     "modeled_key_bytes",
                                                     "modeled_sort_bytes",
                                                     "modeled_permute_bytes",
                                                     "pipeline",
                                                     "gpu_e2e_ms",
                                                     "gpu_e2e_mray_s",
                                                     "trace_ms_lo",
                                                     "trace_ms_hi",
                                                     "e2e_ms_lo",
                                                     "e2e_ms_hi",
                                                     "interval_level",
                                                     "trace_samples_ms",
                                                     "e2e_samples_ms",
                                                     "gen_samples_ms",
                                                     "key_samples_ms",
                                                     "sort_samples_ms",
                                                     "permute_samples_ms",
                                                     "scene_fingerprint",
                                                     "gpu_sms",
                                                     "gpu_driver",
                                                     "cuda_runtime",
                                                     "gpu_sm_mhz_start",
                                                     "gpu_sm_mhz_end",
                                                     "gpu_mem_mhz_start",
                                                     "gpu_mem_mhz_end",
                                                     "git_revision",
                                                     "build_type",
                                                     "compiler",
                                                     "cpu",
                                                     "host",
                                                     "machine",
                                                     "device",
                                                     "embree_version",
                                                     "threads",
                                                     "started_utc",
                                                     "command_line",
                                                     "run_under"};

// The experiment CSV's column order is part of every file already written: pinned here.
TEST(Csv, ExperimentColumnsKeepTheirOrderAndResumeKey) {
  const std::vector<std::string> names = column_names(experiment_schema());
  std::vector<std::string> expected = kExperimentColumns;
  for (const char* c : {"tile_w", "tile_h", "k", "order", "preset", "mode"}) expected.push_back(c);
  for (const std::string& c : hw_column_names()) expected.push_back(c);  // cuda:counters=hw, measured
  EXPECT_EQ(names, expected);
  std::vector<std::string> key;
  for (const auto& c : experiment_schema())
    if (c.key) key.push_back(c.name);
  EXPECT_EQ(key, (std::vector<std::string>{"scene", "pass", "method", "generator_params", "tracer", "tracer_params",
                                           "width", "height", "frame", "seed", "repeats", "encoder_params", "permute",
                                           "git_revision", "build_type", "cpu", "threads", "run_under"}));
}

TEST(Csv, RowsRoundTripThroughTheirSchema) {
  ExperimentRow r;
  r.scene = "cornell";
  r.generator_params = "tile=8x8,k=8";
  r.rays = 12345;
  r.trace_ms = 1.23456;
  r.mray_s = 10.0;
  r.groups_diffuse = 7;
  r.simt_efficiency = 0.123456789;
  r.provenance.threads = 2;
  r.recorded.tile_w = 8;
  r.recorded.k = 16;
  r.recorded.preset = "h100";
  const auto text = write_row(experiment_schema(), r);
  const std::vector<std::string> names = column_names(experiment_schema());
  auto at = [&](const std::string& name) {
    return text[static_cast<size_t>(std::find(names.begin(), names.end(), name) - names.begin())];
  };
  EXPECT_EQ(at("trace_ms"), "1.2346");   // 4 decimals
  EXPECT_EQ(at("mray_s"), "10.000");     // 3 decimals
  EXPECT_EQ(at("below_geometric"), "");  // absent
  EXPECT_EQ(at("groups_diffuse"), "7");
  EXPECT_EQ(at("simt_efficiency"), "0.123457");  // counters: 6 significant digits
  const ExperimentRow back = read_row(experiment_schema(), text);
  EXPECT_EQ(write_row(experiment_schema(), back), text);  // text -> record -> text is exact
  EXPECT_FALSE(back.below_geometric.has_value());
  EXPECT_EQ(back.groups_diffuse, 7u);

  QualityRow q;
  q.psnr = 31.5;
  q.bias2 = std::nan("");
  const auto qt = write_row(quality_schema(), q);
  const QualityRow qb = read_row(quality_schema(), qt);
  EXPECT_TRUE(std::isnan(qb.bias2));  // written empty, read back as NaN
  EXPECT_EQ(write_row(quality_schema(), qb), qt);
}

TEST(Csv, DamagedValuesNameTheirColumn) {
  auto text = write_row(experiment_schema(), ExperimentRow{});
  const std::vector<std::string> names = column_names(experiment_schema());
  const size_t rays = static_cast<size_t>(std::find(names.begin(), names.end(), "rays") - names.begin());
  text[rays] = "lots";
  try {
    read_row(experiment_schema(), text);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("column rays: 'lots' is not an integer"), std::string::npos) << e.what();
  }
  text[rays] = "-3";
  EXPECT_THROW(read_row(experiment_schema(), text), std::invalid_argument);
  text[rays] = "3";
  text[static_cast<size_t>(std::find(names.begin(), names.end(), "trace_ms") - names.begin())] = "1.5ms";
  EXPECT_THROW(read_row(experiment_schema(), text), std::invalid_argument);
}

TEST(Csv, ALineWithADamagedValueIsSkippedNamingLineAndColumn) {
  const auto dir = temp_dir("csv_damaged");
  const auto path = (dir / "e.csv").string();
  std::string header;
  for (const auto& n : column_names(experiment_schema())) header += (header.empty() ? "" : ",") + n;
  auto row = write_row(experiment_schema(), ExperimentRow{});
  std::string good;
  for (size_t i = 0; i < row.size(); ++i) good += (i ? "," : "") + csv_escape(row[i]);
  const std::vector<std::string> names = column_names(experiment_schema());
  row[static_cast<size_t>(std::find(names.begin(), names.end(), "frame") - names.begin())] = "first";
  std::string line;
  for (size_t i = 0; i < row.size(); ++i) line += (i ? "," : "") + csv_escape(row[i]);
  write_file(path + ".partial", header + "\n" + line + "\n" + good + "\n");
  RecordCsv<ExperimentRow> csv(path, experiment_schema(), CsvWriter::Options::resumable(false, {}));
  EXPECT_EQ(csv.resumed().size(), 1u);  // the good row after the damaged one is kept
  const auto aside = read_lines(path + ".rejected");
  ASSERT_EQ(aside.size(), 2u);
  EXPECT_NE(aside[0].find("e.csv.partial line 2: column frame: 'first' is not an integer"), std::string::npos)
      << aside[0];
  EXPECT_EQ(aside[1], line);
}

TEST(Csv, WriteFailuresAreErrors) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const auto dir = temp_dir("csv_full");
  const auto path = (dir / "full.csv").string();
  std::filesystem::create_symlink("/dev/full", path + ".partial");
  EXPECT_THROW(CsvWriter(path, {"a", "b"}, CsvWriter::Options::once(true)), WriteError);
}

}  // namespace
}  // namespace raycoh::test
