// A small Prometheus registry: counters, gauges and fixed-bucket histograms in labelled
// families, written in the text exposition format 0.0.4. Recording is a few atomic
// operations; only looking up a label set's series takes its family's mutex, so callers on
// hot paths keep the reference `with()` returns.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace isocorr::server::metrics {

// Label values in the order of their family's label names.
using LabelValues = std::vector<std::string>;

std::string escape_label_value(std::string_view value);  // \ " and newline escaped
std::string escape_help(std::string_view help);          // \ and newline escaped
std::string format_value(double value);                  // shortest exact form, +Inf, -Inf, NaN

// Builds exposition text: one HELP and TYPE pair per family, then its samples.
class ExpositionWriter {
 public:
  void family(std::string_view name, std::string_view help, std::string_view type);
  void sample(std::string_view name, const std::vector<std::string>& label_names, const LabelValues& values,
              double value);
  void sample(std::string_view name, double value) { sample(name, {}, {}, value); }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

class Counter {
 public:
  void add(double amount = 1) { value_.fetch_add(amount, std::memory_order_relaxed); }
  double value() const { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<double> value_{0};
};

class Gauge {
 public:
  void set(double value) { value_.store(value, std::memory_order_relaxed); }
  void add(double amount) { value_.fetch_add(amount, std::memory_order_relaxed); }
  double value() const { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<double> value_{0};
};

// Counts per bucket are kept apart and summed when written, so a scrape always sees
// cumulative buckets that end in `_count`, even while observations arrive.
class Histogram {
 public:
  explicit Histogram(std::vector<double> upper_bounds);
  void observe(double value);
  const std::vector<double>& upper_bounds() const { return bounds_; }
  std::vector<uint64_t> cumulative_counts() const;  // one per bound, then +Inf
  double sum() const { return sum_.load(std::memory_order_relaxed); }

 private:
  std::vector<double> bounds_;
  std::unique_ptr<std::atomic<uint64_t>[]> counts_;  // bounds_.size() + 1, the last for +Inf
  std::atomic<double> sum_{0};
};

class FamilyBase {
 public:
  FamilyBase(std::string name, std::string help, std::vector<std::string> label_names)
      : name_(std::move(name)), help_(std::move(help)), label_names_(std::move(label_names)) {}
  virtual ~FamilyBase() = default;
  virtual void write(ExpositionWriter& out) const = 0;
  const std::string& name() const { return name_; }

 protected:
  const std::string name_, help_;
  const std::vector<std::string> label_names_;
};

// One metric name and its series, one per distinct set of label values.
template <typename Series>
class Family : public FamilyBase {
 public:
  Family(std::string name, std::string help, std::vector<std::string> label_names, std::vector<double> bounds = {})
      : FamilyBase(std::move(name), std::move(help), std::move(label_names)), bounds_(std::move(bounds)) {}

  Series& with(const LabelValues& values);
  Series& only() { return with({}); }  // for a family without labels
  void write(ExpositionWriter& out) const override;

 private:
  const std::vector<double> bounds_;  // histograms only
  mutable std::mutex mutex_;
  std::map<LabelValues, std::unique_ptr<Series>> series_;  // sorted: stable output
};

using CounterFamily = Family<Counter>;
using GaugeFamily = Family<Gauge>;
using HistogramFamily = Family<Histogram>;

class Registry {
 public:
  CounterFamily& counter(std::string name, std::string help, std::vector<std::string> label_names = {});
  GaugeFamily& gauge(std::string name, std::string help, std::vector<std::string> label_names = {});
  HistogramFamily& histogram(std::string name, std::string help, std::vector<std::string> label_names,
                             std::vector<double> upper_bounds);
  void write(ExpositionWriter& out) const;  // in the order families were added

 private:
  template <typename F>
  F& add(std::unique_ptr<F> family);

  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<FamilyBase>> families_;
};

}  // namespace isocorr::server::metrics
