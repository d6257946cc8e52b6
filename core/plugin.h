// The one shape of every plugin registry (generators, encoders, tracers, built-in scenes): a list of
// PluginInfo records, each with the plugin's name, a one-line summary, its parameter table and its factory.
// The table lives next to the factory, which reads every value through it (core/params.h), so `raycoh list`
// (format_plugins) shows the defaults and ranges that run. No fmt here: cuda/*.cu include this through
// generators/generator.h, and nvcc 13 does not compile fmt's format strings.
#pragma once

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/params.h"

namespace raycoh {

template <class Factory>
struct PluginInfo {
  PluginInfo(std::string name_, std::string summary_, const ParamTable& (*table_)(), Factory make_)
      : name(std::move(name_)),
        summary(std::move(summary_)),
        table(table_),
        make(make_),
        params(param_summary(table_())) {}

  std::string name;
  std::string summary;           // one line for `raycoh list`
  const ParamTable& (*table)();  // the plugin's parameters, declared once next to its factory
  Factory make;                  // reads a ParamSet over table() and builds the plugin
  // "name=default (range), ..." rendered from table(), for the list command until it prints format_plugins().
  std::string params;
};

// The record named name; throws raycoh::Error naming the valid ones ("unknown encoder 'x'; valid encoders: ...").
template <class Info>
const Info& find_plugin(const std::vector<Info>& infos, const std::string& kind, const std::string& name) {
  for (const Info& info : infos)
    if (info.name == name) return info;
  std::vector<std::string> names;
  for (const Info& info : infos) names.push_back(info.name);
  throw Error("unknown " + kind + " '" + name + "'; valid " + kind + "s: " + join(names));
}

// For `raycoh list`: per plugin its name and summary, then its parameter table (name, type, default, range, doc).
template <class Info>
std::string format_plugins(const std::vector<Info>& infos) {
  std::string out;
  for (const Info& info : infos) {
    char head[32];
    std::snprintf(head, sizeof head, "  %-10s ", info.name.c_str());
    out += head + info.summary + "\n" + format_param_table(info.table(), "      ");
  }
  return out;
}

}  // namespace raycoh
