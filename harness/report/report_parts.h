// The parts of `raycoh report` (harness/report/report.cpp: the page and the command): the SVG figures
// (report_figures.cpp, their drawing primitives report_svg.cpp) and the page's sections per kind of CSV
// (report_sections.cpp). The CSVs are read by the results layer (records/result_csv.h, records/experiment_sums.h).
#pragma once

#include <string>
#include <vector>

#include "records/experiment_sums.h"
#include "records/result_csv.h"

namespace raycoh::report_detail {

std::string html_escape(const std::string& s);
std::string base64(const std::string& bytes);

// Okabe & Ito (2008), colour-blind safe; noopt (the baseline) is grey.
extern const char* const kHues[7];
std::string generator_colour(const std::string& generator, const std::vector<std::string>& generators);
std::string lighten(const std::string& hex, double shade);
std::string ramp(double t);
std::string text(double x, double y, const std::string& s, const char* anchor = "middle", int size = 12,
                 const char* extra = "");
std::vector<double> ticks(double hi);

// The footer of a figure: resolution, frames and revision, then the tracers (two lines of SVG text).
std::string footer_of(const Experiment& e, const ResultKey* tracer = nullptr);
std::string table_figure(const Experiment& e, const ResultKey& tl, bool e2e, const std::string& title);
std::string sweep_figure(const Experiment& e, const std::string& scene, const ResultKey& tl);
std::string converge_figure(const ResultCsv& c, const std::string& clock, const std::string& metric);

struct Page {
  std::string html, md;
  std::vector<std::string> provenance;  // one <li> per CSV
};
void add_table(Page& p, const ResultCsv& c);
void add_sweep(Page& p, const ResultCsv& c);
// The rows cuda:counters=hw measured (run_under cupti-counters), their hw_* columns (report_hw.cpp); nothing when
// the CSV has none.
void add_hw_counters(Page& p, const ResultCsv& c, const Experiment& e);
void add_converge(Page& p, const ResultCsv& c);
void add_converge_summary(Page& p, const ResultCsv& c);
void add_quality(Page& p, const ResultCsv& c);
void add_validate(Page& p, const ResultCsv& c);
void add_stability(Page& p, const ResultCsv& c);
void add_tune(Page& p, const ResultCsv& c);          // report_tune.cpp
void add_tune_confirm(Page& p, const ResultCsv& c);  // report_tune.cpp
std::string provenance_of(const ResultCsv& c, const char* kind);

}  // namespace raycoh::report_detail
