// CSV output that never loses what was measured: rows go to "<path>.partial" and are flushed one by one;
// finish() renames the file to <path>. A run that stops early leaves its rows in the .partial file.
#pragma once

#include <fstream>
#include <string>
#include <vector>

namespace raycoh {

class CsvWriter {
 public:
  CsvWriter() = default;
  // Opens <path>.partial and writes the header. Throws raycoh::Error if the file cannot be written.
  CsvWriter(const std::string& path, const std::vector<std::string>& columns);
  void write_row(const std::vector<std::string>& values);
  // Renames <path>.partial to <path>.
  void finish();
  bool is_open() const { return out_.is_open(); }
  const std::string& path() const { return path_; }
  std::string partial_path() const { return path_ + ".partial"; }
  size_t rows() const { return rows_; }

 private:
  std::string path_;
  std::ofstream out_;
  size_t columns_ = 0;
  size_t rows_ = 0;
};

std::string csv_escape(const std::string& field);

}  // namespace raycoh
