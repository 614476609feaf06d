// The metrics registry's text exposition (format 0.0.4): HELP and TYPE lines, escaped
// labels, cumulative histogram buckets ending in +Inf, _sum and _count.
#include "metrics/metrics_registry.h"

#include <limits>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace isocorr::server::metrics {
namespace {

std::string exposition(const Registry& registry) {
  ExpositionWriter out;
  registry.write(out);
  return out.text();
}

TEST(MetricsRegistry, CounterWithHelpTypeAndLabels) {
  Registry registry;
  CounterFamily& calls = registry.counter("calls_total", "Calls by method", {"method", "code"});
  calls.with({"GetJob", "OK"}).add();
  calls.with({"GetJob", "OK"}).add(2);
  calls.with({"GetJob", "NOT_FOUND"}).add();
  EXPECT_EQ(exposition(registry),
            "# HELP calls_total Calls by method\n"
            "# TYPE calls_total counter\n"
            "calls_total{method=\"GetJob\",code=\"NOT_FOUND\"} 1\n"
            "calls_total{method=\"GetJob\",code=\"OK\"} 3\n");
}

TEST(MetricsRegistry, LabelValuesAndHelpAreEscaped) {
  Registry registry;
  registry.gauge("odd", "a \\ backslash\nand a new line", {"path"}).with({"C:\\dir \"x\"\nnext"}).set(-2.5);
  EXPECT_EQ(exposition(registry),
            "# HELP odd a \\\\ backslash\\nand a new line\n"
            "# TYPE odd gauge\n"
            "odd{path=\"C:\\\\dir \\\"x\\\"\\nnext\"} -2.5\n");
  EXPECT_EQ(escape_label_value("plain"), "plain");
}

TEST(MetricsRegistry, SpecialValuesHaveTheirNames) {
  EXPECT_EQ(format_value(std::numeric_limits<double>::infinity()), "+Inf");
  EXPECT_EQ(format_value(-std::numeric_limits<double>::infinity()), "-Inf");
  EXPECT_EQ(format_value(std::numeric_limits<double>::quiet_NaN()), "NaN");
  EXPECT_EQ(format_value(0.1), "0.1");
  EXPECT_EQ(format_value(3), "3");
}

TEST(MetricsRegistry, HistogramBucketsAreCumulativeAndEndInInf) {
  Registry registry;
  HistogramFamily& durations = registry.histogram("job_seconds", "Job time", {"state"}, {0.5, 1, 5});
  Histogram& done = durations.with({"SUCCEEDED"});
  for (double v : {0.25, 0.5, 0.75, 3.0, 9.0}) done.observe(v);  // 0.5 falls in le="0.5"
  EXPECT_EQ(exposition(registry),
            "# HELP job_seconds Job time\n"
            "# TYPE job_seconds histogram\n"
            "job_seconds_bucket{state=\"SUCCEEDED\",le=\"0.5\"} 2\n"
            "job_seconds_bucket{state=\"SUCCEEDED\",le=\"1\"} 3\n"
            "job_seconds_bucket{state=\"SUCCEEDED\",le=\"5\"} 4\n"
            "job_seconds_bucket{state=\"SUCCEEDED\",le=\"+Inf\"} 5\n"
            "job_seconds_sum{state=\"SUCCEEDED\"} 13.5\n"
            "job_seconds_count{state=\"SUCCEEDED\"} 5\n");
}

TEST(MetricsRegistry, FamiliesKeepTheirOrderAndRefuseMistakes) {
  Registry registry;
  registry.gauge("b_first", "first").only().set(1);
  registry.counter("a_second", "second");  // no series yet: HELP and TYPE only
  EXPECT_EQ(exposition(registry),
            "# HELP b_first first\n# TYPE b_first gauge\nb_first 1\n"
            "# HELP a_second second\n# TYPE a_second counter\n");
  EXPECT_THROW(registry.counter("b_first", "again"), std::logic_error);
  EXPECT_THROW(registry.histogram("h", "bounds must increase", {}, {1, 1}), std::logic_error);
  EXPECT_THROW(registry.counter("c", "one label", {"x"}).with({"1", "2"}), std::logic_error);
}

// Counts from several threads all arrive (atomics, no lost updates).
TEST(MetricsRegistry, ConcurrentUpdatesAreAllCounted) {
  Registry registry;
  CounterFamily& counter = registry.counter("n_total", "n", {"worker"});
  Histogram& histogram = registry.histogram("h", "h", {}, {1}).only();
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 10000; ++i) {
        counter.with({"w"}).add();
        histogram.observe(i % 2);
      }
    });
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(counter.with({"w"}).value(), 40000);
  EXPECT_EQ(histogram.cumulative_counts(), (std::vector<uint64_t>{40000, 40000}));
  EXPECT_EQ(histogram.sum(), 20000);
}

}  // namespace
}  // namespace isocorr::server::metrics
