#include <fmt/core.h>

#include <filesystem>
#include <omnidso/cli/eval_plot.hpp>
#include <omnidso/cli/line_plot.hpp>
#include <omnidso/core/error.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace omnidso::cli {

void writeEvaluationPlot(const std::string& path, const Trajectory& gt,
                         const EvaluationResult& result, const std::optional<ScaleDrift>& drift) {
  if (std::filesystem::exists(path)) throw Error(path + ": exists; not overwritten");
  const double t0 = gt[result.association.front().first].timestamp;
  LinePlot ate(fmt::format("ATE after {} alignment (RMSE {:.4f} m)", "Sim(3)", result.ate.rmse),
               "time [s]", "ATE [m]");
  ate.setIncludeZeroY(true);
  PlotSeries errors{"per-pose error", seriesColour(0), {}};
  for (size_t k = 0; k < result.association.size(); ++k)
    errors.points.emplace_back(gt[result.association[k].first].timestamp - t0,
                               result.position_errors[k]);
  ate.addSeries(std::move(errors));

  LinePlot scale(drift ? fmt::format("local scale over {:.2f} m of path ({:+.2f} % over the "
                                     "sequence, {:+.2f} % per 10 m)",
                                     drift->window_m, drift->percent_over_sequence,
                                     drift->percent_per_10m)
                       : std::string("local scale: too short for three windows"),
                 "time [s]", "estimated / true length");
  if (drift) {
    PlotSeries ratio{"local scale", seriesColour(1), {}};
    for (const LocalScale& s : drift->samples) ratio.points.emplace_back(s.time_s, s.ratio);
    scale.addSeries(std::move(ratio));
    PlotSeries one{"drift-free", cv::Scalar(0, 0, 0), {}, 1};
    one.points = {{0.0, 1.0}, {drift->samples.back().time_s, 1.0}};
    scale.addSeries(std::move(one));
  }
  cv::Mat image;
  cv::vconcat(ate.render(1100, 420), scale.render(1100, 420), image);
  if (!cv::imwrite(path, image)) throw Error(path + ": cannot write the PNG");
}

}  // namespace omnidso::cli
