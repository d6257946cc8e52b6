// Liu et al., "Generate Coherent Rays Directly", Eurographics 2024: the paper's measured tables (an RTX 3060 at
// 1920x1080, MRay/s of the secondary rays' trace), the validation set of `raycoh validate`. Compared against,
// never used to set a parameter.
#pragma once

namespace raycoh::paper {

// Table 1's rows: our method label and the paper's row name.
struct Table1Row {
  const char* row;
  const char* paper;
};
inline constexpr Table1Row kTable1Rows[] = {
    {"noopt", "NoOpt"},
    {"ours:tile=8x8,k=8", "Ours"},
    {"noopt+mlhcc", "MLHCC32"},
    {"noopt+twopoint", "TwoPoint"},
    {"noopt+aila", "AilaCompact"},
    {"noopt+reis", "Reis"},
    {"noopt+origin", "Origin"},
};
inline constexpr int kTable1RowCount = 7;

// Table 1's columns: the paper's scene, the scene raycoh stands in for it with (a folder of that name, README
// "Real scenes"), and the MRay/s of each row above.
struct Table1Column {
  const char* paper_scene;
  const char* stand_in;
  double mray_s[kTable1RowCount];
};
inline constexpr Table1Column kTable1[] = {
    {"Breakfast", "country_kitchen", {37.4, 58.6, 65.1, 56.8, 55.6, 49.7, 46.1}},
    {"Salle de Bain", "contemporary_bathroom", {206.1, 305.6, 280.2, 274.2, 268.0, 242.4, 233.0}},
    {"Living room", "modern_living_room", {189.4, 287.9, 277.8, 272.1, 258.2, 224.8, 208.3}},
    {"Sibenik", "sibenik", {154.7, 278.5, 218.5, 217.9, 208.9, 183.2, 165.4}},
    {"Vokselia", "lost_empire", {64.2, 87.5, 74.4, 75.5, 75.5, 74.3, 74.8}},
};
inline constexpr int kSibenik = 3;  // Table 1's Sibenik column, the scene of Table 3

// Table 3 (ours on Sibenik): tile W x H down, group size K across.
inline constexpr int kTiles[4][2] = {{8, 8}, {16, 8}, {16, 16}, {32, 8}};
inline constexpr int kGroups[4] = {8, 16, 32, 64};
inline constexpr double kTable3[4][4] = {{278.5, 303.9, 378.0, 379.4},
                                         {234.1, 290.4, 338.9, 337.7},
                                         {232.5, 273.9, 305.2, 306.6},
                                         {227.1, 255.0, 298.9, 298.5}};

}  // namespace raycoh::paper
