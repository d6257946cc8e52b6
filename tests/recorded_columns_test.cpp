// The typed recorded parameters (records/recorded_columns.h): read through the plugins' own tables from the
// parameter text a row records, written as the CSV's last columns, read back by the report's data access
// (records/result_csv.h) from those columns or, for a CSV written before them, from the text; and a resume of such
// an older file refused naming the column it lacks.
#include "records/recorded_columns.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "generators/generator.h"
#include "records/csv.h"
#include "records/experiment_row.h"
#include "records/hw_columns.h"
#include "records/result_csv.h"
#include "tests/test_util.h"

namespace raycoh::test {
namespace {

TEST(RecordedColumns, ReadThroughThePluginTables) {
  const RecordedColumns ours = recorded_columns("ours", "tile=16x8,k=32,order=group,seed=0,hybrid=paper,frame=duff",
                                                "simt", "preset=h100,kernel=persistent");
  EXPECT_EQ(ours.tile_w, 16);
  EXPECT_EQ(ours.tile_h, 8);
  EXPECT_EQ(ours.k, 32);
  EXPECT_EQ(ours.order, "group");
  EXPECT_EQ(ours.preset, "h100");
  EXPECT_EQ(ours.mode, "");
  // Defaults where the text leaves a parameter out; no K for noopt; the primary pass is noopt's order.
  const RecordedColumns noopt = recorded_columns("noopt", "", "embree", "mode=packet16");
  EXPECT_EQ(noopt.tile_w, 8);
  EXPECT_FALSE(noopt.k.has_value());
  EXPECT_EQ(noopt.order, "tile");
  EXPECT_EQ(noopt.mode, "packet16");
  EXPECT_EQ(recorded_columns("primary", "order=tile,tile=8x8", "cpu", "").order, "tile");
  // `tile` is contiguous's old name; a name no registry knows gives empty columns.
  EXPECT_EQ(recorded_columns("tile", "tile=4x4,k=2", "cpu", "").k, 2);
  const RecordedColumns unknown = recorded_columns("gone", "k=3", "gone", "preset=x");
  EXPECT_FALSE(unknown.k.has_value());
  EXPECT_EQ(unknown.preset, "");
  EXPECT_EQ(result_key("simt", "preset=h100,l1_tags=4", "bvh2", ours).label(), "simt[preset=h100]");
  EXPECT_EQ(result_key("simt", "preset=h100,l1_tags=4", "bvh2", ours).label(true), "simt[preset=h100,l1_tags=4]");
  EXPECT_EQ(result_key("embree", "mode=packet16", "", noopt).label(), "embree[mode=packet16]");
  EXPECT_EQ(result_key("cpu", "", "bvh2", recorded_columns("noopt", "", "cpu", "")).label(true), "cpu");
  EXPECT_EQ(sweep_method_label("ours", 16, 8, 32), "ours:tile=16x8,k=32");
}

// Headings name a tracer by its short label, or by every parameter where two tracers would share it.
TEST(RecordedColumns, HeadingLabelsAreShortUnlessShared) {
  const ResultKey cuda{"cuda", "", "", "bvh2", "kernel=persistent"}, cwbvh{"cuda", "", "", "cwbvh", "bvh=cwbvh"},
      simt{"simt", "h100", "", "bvh2", "preset=h100"};
  const std::map<ResultKey, std::string> names = heading_labels({cuda, cwbvh, simt, cuda});
  EXPECT_EQ(names.at(cuda), "cuda[kernel=persistent]");
  EXPECT_EQ(names.at(cwbvh), "cuda[bvh=cwbvh]");
  EXPECT_EQ(names.at(simt), "simt[preset=h100]");
  EXPECT_EQ(heading_labels({cuda}).at(cuda), "cuda");
}

// A CSV of the experiment schema with its typed columns, and the same rows without them (an older file): the
// report's data access reads the same typed values from both.
// A generator that ran gives its K, tile and order typed (Generator::layout()): the same columns its canonical
// parameter text reads as, without reading the text back; generators without a typed layout are read from it.
TEST(RecordedColumns, AGeneratorThatRanGivesItsLayoutTyped) {
  for (const char* spec : {"ours:tile=16x8,k=32,order=group", "contiguous:k=4", "noopt", "direct:tile=4x4"}) {
    const PluginSpec p = parse_plugin_spec(spec);
    const std::unique_ptr<Generator> g = make_generator(p);
    const RecordedColumns typed = recorded_columns(p.name, *g, "cpu", "");
    const RecordedColumns text = recorded_columns(p.name, g->params(), "cpu", "");
    EXPECT_EQ(typed.tile_w, text.tile_w) << spec;
    EXPECT_EQ(typed.tile_h, text.tile_h) << spec;
    EXPECT_EQ(typed.k, text.k) << spec;
    EXPECT_EQ(typed.order, text.order) << spec;
    EXPECT_EQ(g->layout().has_value(), p.name == "ours" || p.name == "contiguous") << spec;
  }
  const std::unique_ptr<Generator> ours = make_generator(parse_plugin_spec("ours:tile=16x8,k=32"));
  EXPECT_EQ(ours->layout()->k, 32);
}

TEST(RecordedColumns, OlderFilesAreReadThroughTheTextOnce) {
  const auto dir = temp_dir("recorded_columns");
  ExperimentRow r;
  r.scene = "cornell";
  r.pass = "secondary";
  r.method = sweep_method_label("ours", 16, 8, 32);
  r.generator = "ours";
  r.generator_params = "tile=16x8,k=32,order=tile";
  r.tracer = "simt";
  r.tracer_params = "preset=rtx3060";
  set_recorded_params(r);
  const std::vector<std::string> names = column_names(experiment_schema()), fields = write_row(experiment_schema(), r);
  // A file written before the typed columns: without them and without the hw_* columns that follow them.
  const size_t old_width = names.size() - recorded_schema().size() - hw_column_names().size();
  const auto line = [](const std::vector<std::string>& v, size_t n) {
    std::string s;
    for (size_t i = 0; i < n; ++i) s += (i ? "," : "") + csv_escape(v[i]);
    return s + "\n";
  };
  write_file((dir / "new.csv").string(), line(names, names.size()) + line(fields, fields.size()));
  write_file((dir / "old.csv").string(), line(names, old_width) + line(fields, old_width));
  for (const char* file : {"new.csv", "old.csv"}) {
    const ResultCsv c = read_result_csv((dir / file).string());
    const RecordedColumns got = recorded_of(c, c.rows.at(0));
    EXPECT_EQ(got.k, 32) << file;
    EXPECT_EQ(got.preset, "rtx3060") << file;
    EXPECT_TRUE(sweep_cell(r.method, "ours", got).has_value()) << file;
  }
  // Resuming the older file is refused, naming the first column it lacks.
  const std::string old_path = (dir / "old.csv").string();
  const std::string e = error_of([&] { CsvWriter(old_path, names, CsvWriter::Options::resumable(false, {})); });
  EXPECT_NE(e.find("lacks the column 'tile_w'"), std::string::npos) << e;
}

}  // namespace
}  // namespace raycoh::test
