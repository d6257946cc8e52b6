// Results are never lost or silently wrong, at the level of the file layer (records/csv.h, core/durable_file.h):
// damaged resume files keep every good row, foreign files are refused by field, finished files are not
// rewritten, locks name their holder, refused writes keep whole rows and leave no temp file.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/durable_file.h"
#include "core/error.h"
#include "records/csv.h"
#include "tests/cli_util.h"

namespace raycoh::test {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kColumns = {"name", "value", "git_revision"};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// No ".<name>.tmp<pid>" file and no lock file left in `dir`.
void expect_no_leftovers(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
    EXPECT_NE(e.path().extension(), ".lock") << name;
  }
}

// Lowers the file size limit (in bytes) for one scope; SIGXFSZ is ignored so writes fail with EFBIG.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &old_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit lim = old_;
    lim.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &lim);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }

 private:
  rlimit old_{};
  void (*old_handler_)(int) = nullptr;
};

TEST(ResultsSafety, EveryDamagedLineIsSkippedNamedAndKeptAside) {
  const auto dir = temp_dir("safety_lines");
  const std::string path = (dir / "r.csv").string();
  // CRLF endings, then: a good row, an empty line, a NUL byte, unbalanced quotes, a short row, a value the check
  // rejects, a good row, a torn last line.
  const std::string text = std::string("name,value,git_revision\r\na,1,rev\r\n\r\nb,2") + std::string(1, '\0') +
                           "x,rev\r\n\"c,3,rev\r\nd,4\r\ne,bad,rev\r\nf,6,rev\r\ng,7";
  write_file(path + ".partial", text);
  auto o = CsvWriter::Options::resumable(false, {});
  o.check_values = [](const std::vector<std::string>& f) {
    return f[1] == "bad" ? std::string("column value: 'bad' is not a number") : std::string();
  };
  {
    CsvWriter csv(path, kColumns, o);
    ASSERT_EQ(csv.resumed_rows().size(), 2u);
    EXPECT_EQ(csv.resumed_rows()[0][0], "a");
    EXPECT_EQ(csv.resumed_rows()[1][0], "f");  // every good row after the damaged ones is kept
    csv.write_row({"h", "8", "rev"});
    csv.finish();
  }
  EXPECT_EQ(slurp(path), "name,value,git_revision\na,1,rev\nf,6,rev\nh,8,rev\n");
  const auto aside = read_lines(path + ".rejected");
  ASSERT_EQ(aside.size(), 12u);  // a comment line naming line and reason, then the line itself, six times
  EXPECT_NE(aside[0].find("r.csv.partial line 3: empty line"), std::string::npos) << aside[0];
  EXPECT_NE(aside[2].find("line 4: NUL byte"), std::string::npos) << aside[2];
  EXPECT_NE(aside[4].find("line 5: unbalanced quotes"), std::string::npos) << aside[4];
  EXPECT_NE(aside[6].find("line 6: 2 fields for 3 columns"), std::string::npos) << aside[6];
  EXPECT_NE(aside[8].find("line 7: column value: 'bad' is not a number"), std::string::npos) << aside[8];
  EXPECT_NE(aside[10].find("line 9: torn last line"), std::string::npos) << aside[10];
  expect_no_leftovers(dir);
}

TEST(ResultsSafety, AFileOfOtherColumnsIsRefusedUnlessForced) {
  const auto dir = temp_dir("safety_header");
  const std::string path = (dir / "r.csv").string();
  write_file(path + ".partial", "name,amount,git_revision\na,1,rev\n");
  const std::string e = error_of([&] { CsvWriter(path, kColumns, CsvWriter::Options::resumable(false, {})); });
  EXPECT_NE(e.find("column 2 is 'amount', this version writes 'value'"), std::string::npos) << e;
  EXPECT_NE(e.find("--force"), std::string::npos) << e;
  EXPECT_EQ(slurp(path + ".partial"), "name,amount,git_revision\na,1,rev\n");  // refused: untouched
  CsvWriter forced(path, kColumns, CsvWriter::Options::resumable(true, {}));
  EXPECT_TRUE(forced.resumed_rows().empty());
}

TEST(ResultsSafety, RowsOfOtherParametersAreRefusedNamingTheField) {
  const auto dir = temp_dir("safety_rule");
  const std::string path = (dir / "r.csv").string();
  write_file(path, "name,value,git_revision\na,1,rev1\nb,2,rev1\n");
  ResumeRule rule;
  rule.require("git_revision", {"rev2"});
  const std::string e = error_of([&] { CsvWriter(path, kColumns, CsvWriter::Options::resumable(false, rule)); });
  EXPECT_NE(e.find("r.csv line 2 was measured with other parameters: its git_revision is 'rev1', this run's is "
                   "'rev2'"),
            std::string::npos)
      << e;
  EXPECT_EQ(slurp(path), "name,value,git_revision\na,1,rev1\nb,2,rev1\n");
  EXPECT_FALSE(fs::exists(path + ".partial"));
}

TEST(ResultsSafety, AFinishedFileIsResumedAndLeftByteForByteWhenNothingIsNew) {
  const auto dir = temp_dir("safety_finished");
  const std::string path = (dir / "r.csv").string();
  const std::string finished = "name,value,git_revision\na,1,rev\nb,2,rev\n";
  write_file(path, finished);
  const auto mtime = fs::last_write_time(path);
  {
    CsvWriter csv(path, kColumns, CsvWriter::Options::resumable(false, {}));
    EXPECT_EQ(csv.resumed_rows().size(), 2u);
    csv.finish();
  }
  EXPECT_EQ(slurp(path), finished);
  EXPECT_EQ(fs::last_write_time(path), mtime);
  EXPECT_FALSE(fs::exists(path + ".partial"));
  {
    CsvWriter csv(path, kColumns, CsvWriter::Options::resumable(false, {}));
    csv.write_row({"c", "3", "rev"});  // extends it with the row it lacked
    csv.finish();
  }
  EXPECT_EQ(slurp(path), finished + "c,3,rev\n");
  expect_no_leftovers(dir);
}

TEST(ResultsSafety, AOneShotFileIsRefusedUnlessForcedOrWrittenByTheSameCommand) {
  const auto dir = temp_dir("safety_once");
  const std::string path = (dir / "r.csv").string();
  write_file(path, "name,value,git_revision\na,1,rev\n");
  const std::string e = error_of([&] { CsvWriter(path, kColumns, CsvWriter::Options::once(false)); });
  EXPECT_NE(e.find("already holds a finished run (1 rows); pass --force"), std::string::npos) << e;
  {
    CsvWriter same(path, kColumns, CsvWriter::Options::once(false, {{"git_revision", "rev"}}));
    EXPECT_TRUE(same.already_complete());
  }
  EXPECT_EQ(slurp(path), "name,value,git_revision\na,1,rev\n");
  {
    CsvWriter forced(path, kColumns, CsvWriter::Options::once(true));
    forced.write_row({"z", "9", "rev"});
    EXPECT_EQ(slurp(path), "name,value,git_revision\na,1,rev\n");  // replaced only when the new run finishes
    forced.finish();
  }
  EXPECT_EQ(slurp(path), "name,value,git_revision\nz,9,rev\n");
}

TEST(ResultsSafety, ALockedOutputIsRefusedNamingItsHolder) {
  const auto dir = temp_dir("safety_lock");
  const std::string path = (dir / "r.csv").string();
  {
    const OutputLock held(path, "--out " + path);
    const std::string e = error_of([&] { CsvWriter(path, kColumns, CsvWriter::Options::resumable(false, {})); });
    EXPECT_NE(e.find("is being written by another run (pid " + std::to_string(::getpid())), std::string::npos) << e;
    EXPECT_FALSE(fs::exists(path + ".partial"));
  }
  EXPECT_FALSE(fs::exists(path + ".lock"));  // released and removed
  // A lock file left by a killed run holds no lock: the next run takes it over.
  write_file(path + ".lock", "pid 1 on elsewhere since long ago: raycoh table\n");
  CsvWriter csv(path, kColumns, CsvWriter::Options::resumable(false, {}));
  csv.finish();
  EXPECT_FALSE(fs::exists(path + ".lock"));
}

TEST(ResultsSafety, ARefusedWriteKeepsEveryWholeRowAndNamesTheFile) {
  const auto dir = temp_dir("safety_fsize");
  const std::string path = (dir / "r.csv").string();
  size_t written = 0;
  std::string e;
  {
    CsvWriter csv(path, kColumns, CsvWriter::Options::resumable(false, {}));
    const FileSizeLimit limit(200);
    try {
      for (int i = 0; i < 100; ++i, ++written) csv.write_row({"row" + std::to_string(i), "12345", "rev"});
    } catch (const WriteError& err) {
      e = err.what();
    }
  }
  EXPECT_NE(e.find("writing " + path + ".partial failed: File too large"), std::string::npos) << e;
  ASSERT_GT(written, 2u);
  const std::string kept = slurp(path + ".partial");
  EXPECT_EQ(kept.back(), '\n');                                                             // no torn row
  EXPECT_EQ(static_cast<size_t>(std::count(kept.begin(), kept.end(), '\n')), 1 + written);  // header + rows
  EXPECT_FALSE(fs::exists(path));
  CsvWriter resumed(path, kColumns, CsvWriter::Options::resumable(false, {}));
  EXPECT_EQ(resumed.resumed_rows().size(), written);
}

TEST(ResultsSafety, AnAtomicWriteIsWholeOrAbsentAndLeavesNoTempFile) {
  const auto dir = temp_dir("safety_atomic");
  const std::string path = (dir / "f.bin").string();
  write_file_atomically(path, "old content");
  {
    const FileSizeLimit limit(1000);
    EXPECT_THROW(write_file_atomically(path, std::string(5000, 'x')), WriteError);
  }
  EXPECT_EQ(slurp(path), "old content");  // the refused write left the earlier file as it was
  expect_no_leftovers(dir);
  write_file_atomically(path, "new content");
  EXPECT_EQ(slurp(path), "new content");
}

TEST(ResultsSafety, OutputPathsAreCheckedBeforeAnyWork) {
  const auto dir = temp_dir("safety_paths");
  EXPECT_NE(error_of([&] { check_output_file("--out", dir.string()); }).find("is a folder"), std::string::npos);
  write_file(dir / "file", "x");
  EXPECT_NE(error_of([&] { check_output_folder("--cache", (dir / "file").string()); }).find("is a file, not a folder"),
            std::string::npos);
  EXPECT_NE(error_of([&] { check_output_file("--out", (dir / "file" / "x.csv").string()); }).find("is a file"),
            std::string::npos);
  if (::geteuid() != 0) {  // root writes anywhere
    fs::create_directories(dir / "ro");
    fs::permissions(dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_NE(error_of([&] { check_output_file("--out", (dir / "ro" / "x.csv").string()); }).find("not writable"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace raycoh::test
