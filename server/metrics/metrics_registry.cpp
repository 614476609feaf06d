#include "metrics/metrics_registry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <spdlog/fmt/fmt.h>

namespace isocorr::server::metrics {

std::string escape_label_value(std::string_view value) {
  std::string out;
  out.reserve(value.size());
  for (char c : value) {
    if (c == '\\') out += "\\\\";
    else if (c == '"') out += "\\\"";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

std::string escape_help(std::string_view help) {
  std::string out;
  out.reserve(help.size());
  for (char c : help) {
    if (c == '\\') out += "\\\\";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

std::string format_value(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  return fmt::format("{}", value);  // shortest text that reads back as the same double
}

void ExpositionWriter::family(std::string_view name, std::string_view help, std::string_view type) {
  text_.append("# HELP ").append(name).append(" ").append(escape_help(help)).append("\n");
  text_.append("# TYPE ").append(name).append(" ").append(type).append("\n");
}

void ExpositionWriter::sample(std::string_view name, const std::vector<std::string>& label_names,
                              const LabelValues& values, double value) {
  text_.append(name);
  if (!label_names.empty()) {
    text_ += '{';
    for (size_t i = 0; i < label_names.size(); ++i) {
      if (i > 0) text_ += ',';
      text_.append(label_names[i]).append("=\"").append(escape_label_value(values.at(i))).append("\"");
    }
    text_ += '}';
  }
  text_.append(" ").append(format_value(value)).append("\n");
}

Histogram::Histogram(std::vector<double> upper_bounds)
    : bounds_(std::move(upper_bounds)), counts_(new std::atomic<uint64_t>[bounds_.size() + 1]) {
  if (!std::is_sorted(bounds_.begin(), bounds_.end()) ||
      std::adjacent_find(bounds_.begin(), bounds_.end()) != bounds_.end())
    throw std::logic_error("histogram bounds must increase");
  for (size_t i = 0; i <= bounds_.size(); ++i) counts_[i].store(0);
}

void Histogram::observe(double value) {
  // Buckets are "less than or equal": the first bound not below the value.
  const size_t bucket = std::lower_bound(bounds_.begin(), bounds_.end(), value) - bounds_.begin();
  counts_[bucket].fetch_add(1, std::memory_order_relaxed);
  sum_.fetch_add(value, std::memory_order_relaxed);
}

std::vector<uint64_t> Histogram::cumulative_counts() const {
  std::vector<uint64_t> counts(bounds_.size() + 1);
  uint64_t running = 0;
  for (size_t i = 0; i <= bounds_.size(); ++i) counts[i] = running += counts_[i].load(std::memory_order_relaxed);
  return counts;
}

namespace {

template <typename Series>
std::unique_ptr<Series> make_series(const std::vector<double>&) {
  return std::make_unique<Series>();
}
template <>
std::unique_ptr<Histogram> make_series<Histogram>(const std::vector<double>& bounds) {
  return std::make_unique<Histogram>(bounds);
}

void write_series(ExpositionWriter& out, const std::string& name, const std::vector<std::string>& label_names,
                  const LabelValues& values, const Counter& counter) {
  out.sample(name, label_names, values, counter.value());
}
void write_series(ExpositionWriter& out, const std::string& name, const std::vector<std::string>& label_names,
                  const LabelValues& values, const Gauge& gauge) {
  out.sample(name, label_names, values, gauge.value());
}
void write_series(ExpositionWriter& out, const std::string& name, const std::vector<std::string>& label_names,
                  const LabelValues& values, const Histogram& histogram) {
  std::vector<std::string> bucket_names = label_names;
  bucket_names.push_back("le");
  LabelValues bucket_values = values;
  bucket_values.emplace_back();
  const std::vector<uint64_t> counts = histogram.cumulative_counts();
  const std::vector<double>& bounds = histogram.upper_bounds();
  for (size_t i = 0; i < counts.size(); ++i) {
    bucket_values.back() = i < bounds.size() ? format_value(bounds[i]) : "+Inf";
    out.sample(name + "_bucket", bucket_names, bucket_values, static_cast<double>(counts[i]));
  }
  out.sample(name + "_sum", label_names, values, histogram.sum());
  out.sample(name + "_count", label_names, values, static_cast<double>(counts.back()));
}

template <typename Series>
const char* type_name();
template <> const char* type_name<Counter>() { return "counter"; }
template <> const char* type_name<Gauge>() { return "gauge"; }
template <> const char* type_name<Histogram>() { return "histogram"; }

}  // namespace

template <typename Series>
Series& Family<Series>::with(const LabelValues& values) {
  if (values.size() != label_names_.size())
    throw std::logic_error("metric " + name_ + " takes " + std::to_string(label_names_.size()) + " label value(s)");
  std::lock_guard lock(mutex_);
  std::unique_ptr<Series>& series = series_[values];
  if (!series) series = make_series<Series>(bounds_);
  return *series;
}

template <typename Series>
void Family<Series>::write(ExpositionWriter& out) const {
  out.family(name_, help_, type_name<Series>());
  std::lock_guard lock(mutex_);
  for (const auto& [values, series] : series_) write_series(out, name_, label_names_, values, *series);
}

template class Family<Counter>;
template class Family<Gauge>;
template class Family<Histogram>;

template <typename F>
F& Registry::add(std::unique_ptr<F> family) {
  std::lock_guard lock(mutex_);
  for (const auto& existing : families_)
    if (existing->name() == family->name()) throw std::logic_error("metric " + family->name() + " added twice");
  F& added = *family;
  families_.push_back(std::move(family));
  return added;
}

CounterFamily& Registry::counter(std::string name, std::string help, std::vector<std::string> label_names) {
  return add(std::make_unique<CounterFamily>(std::move(name), std::move(help), std::move(label_names)));
}

GaugeFamily& Registry::gauge(std::string name, std::string help, std::vector<std::string> label_names) {
  return add(std::make_unique<GaugeFamily>(std::move(name), std::move(help), std::move(label_names)));
}

HistogramFamily& Registry::histogram(std::string name, std::string help, std::vector<std::string> label_names,
                                     std::vector<double> upper_bounds) {
  Histogram check(upper_bounds);  // refuse bad bounds here, not at the first observation
  return add(std::make_unique<HistogramFamily>(std::move(name), std::move(help), std::move(label_names),
                                               std::move(upper_bounds)));
}

void Registry::write(ExpositionWriter& out) const {
  std::lock_guard lock(mutex_);
  for (const auto& family : families_) family->write(out);
}

}  // namespace isocorr::server::metrics
