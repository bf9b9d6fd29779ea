#include "kerf/app/TradePlot.hpp"

#include "kerf/app/Format.hpp"
#include "kerf/document/AtomicFile.hpp"

#include <QApplication>
#include <QBuffer>
#include <QFont>
#include <QGraphicsLayout>
#include <QGraphicsRectItem>
#include <QGraphicsScene>
#include <QGraphicsSimpleTextItem>
#include <QImage>
#include <QPainter>
#include <QtCharts/QChart>
#include <QtCharts/QLegend>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

namespace kerf {

namespace {

constexpr int kPanelWidth = 820, kPanelHeight = 700, kHeader = 70;
constexpr double kSmallest = 1e-6; // log axes cannot show 0: zeros are drawn here and labelled so

const QColor kScreenColour(31, 119, 180);
const QColor kExportColour(217, 95, 2);
const QColor kExactColour(44, 160, 44);

struct PlotPoint {
    double x = 0.0, y = 0.0;
    QString label;
};

struct Curve {
    QString name;
    QColor colour;
    std::vector<PlotPoint> points;
};

// An axis range around [lo, hi] with room for the points and their labels
// (a factor of 1.6 each side), and at least two labelled decades: Qt labels
// a log axis only at powers of ten inside its range.
std::pair<double, double> axisRange(double lo, double hi)
{
    double a = lo / 1.6, b = hi * 1.6;
    if (std::floor(std::log10(b)) - std::ceil(std::log10(a)) < 1.0) {
        // A hair wider than the decades: pow(10, -2) may land just inside otherwise.
        a = std::pow(10.0, std::floor(std::log10(a))) * 0.999;
        b = std::pow(10.0, std::ceil(std::log10(b))) * 1.001;
    }
    return {a, b};
}

QChart* makePanel(const QString& title, const QString& xTitle, const std::vector<Curve>& curves)
{
    auto* chart = new QChart;
    chart->setTitle(title);
    QFont titleFont = chart->titleFont();
    titleFont.setPointSize(14);
    titleFont.setBold(true);
    chart->setTitleFont(titleFont);
    chart->legend()->setAlignment(Qt::AlignBottom);
    QFont legendFont = chart->legend()->font();
    legendFont.setPointSize(10);
    chart->legend()->setFont(legendFont);
    chart->setBackgroundRoundness(0);

    double xlo = HUGE_VAL, xhi = 0.0, ylo = HUGE_VAL, yhi = 0.0;
    for (const Curve& c : curves)
        for (const PlotPoint& p : c.points) {
            xlo = std::min(xlo, p.x);
            xhi = std::max(xhi, p.x);
            ylo = std::min(ylo, p.y);
            yhi = std::max(yhi, p.y);
        }
    auto* x = new QLogValueAxis;
    auto* y = new QLogValueAxis;
    for (const auto& [axis, text] :
         {std::pair<QLogValueAxis*, QString>{x, xTitle}, std::pair<QLogValueAxis*, QString>{y, "error (mm)"}}) {
        axis->setBase(10.0);
        axis->setLabelFormat("%g");
        axis->setMinorTickCount(8);
        axis->setTitleText(text);
        QFont f = axis->titleFont();
        f.setPointSize(11);
        axis->setTitleFont(f);
    }
    if (xhi > 0.0) {
        const auto [a, b] = axisRange(xlo, xhi);
        x->setRange(a, b);
    }
    if (yhi > 0.0) {
        const auto [a, b] = axisRange(ylo, yhi);
        y->setRange(a, b);
    }
    chart->addAxis(x, Qt::AlignBottom);
    chart->addAxis(y, Qt::AlignLeft);
    for (const Curve& c : curves) {
        auto* series = new QLineSeries;
        series->setName(c.name);
        for (const PlotPoint& p : c.points)
            series->append(p.x, p.y);
        QPen pen(c.colour);
        pen.setWidthF(2.5);
        series->setPen(pen);
        series->setPointsVisible(true);
        series->setMarkerSize(9.0);
        chart->addSeries(series);
        series->attachAxis(x);
        series->attachAxis(y);
    }
    return chart;
}

// Labels each point with its feature size, beside the point; done after the
// chart's layout, when mapToPosition knows the plot area.
void labelPoints(QChart* chart, const std::vector<Curve>& curves)
{
    const auto series = chart->series();
    for (std::size_t i = 0; i < curves.size() && i < std::size_t(series.size()); ++i)
        for (const PlotPoint& p : curves[i].points) {
            const QPointF at = chart->mapToPosition(QPointF(p.x, p.y), series[qsizetype(i)]);
            // On a white box above the lines, so that no line strikes it through.
            auto* box = new QGraphicsRectItem(chart);
            auto* text = new QGraphicsSimpleTextItem(p.label, box);
            QFont f = text->font();
            f.setPointSize(10);
            f.setBold(true);
            text->setFont(f);
            text->setBrush(curves[i].colour.darker(130));
            const QRectF r = text->boundingRect().adjusted(-3.0, -1.0, 3.0, 1.0);
            box->setRect(r);
            box->setBrush(QColor(255, 255, 255, 225));
            box->setPen(Qt::NoPen);
            box->setZValue(1000.0);
            // Above and to the right of the point, unless that leaves the plot.
            const QRectF plot = chart->plotArea();
            QPointF pos = at + QPointF(9.0, -r.height() - 6.0);
            if (pos.x() + r.width() > plot.right()) pos.setX(at.x() - 9.0 - r.width());
            if (pos.y() < plot.top()) pos.setY(at.y() + 6.0);
            box->setPos(pos);
        }
}

} // namespace

void writeTradePlot(const TradeReport& report, const std::string& title, const std::filesystem::path& png)
{
    // A QApplication for this call only, on the offscreen platform. Qt keeps
    // (and edits) argc and argv: they outlive the application.
    char program[] = "kerf", option[] = "-platform", platform[] = "offscreen";
    char* argv[] = {program, option, platform, nullptr};
    int argc = 3;
    std::unique_ptr<QApplication> app;
    if (!QCoreApplication::instance()) app = std::make_unique<QApplication>(argc, argv);

    // The legend names what is measured; the axis titles say against what.
    // Short names: the legend gives each a third of the panel's width.
    const QString screenName = "Screen: depth error, p99";
    const QString exportName = "Export: mesh's max distance";
    Curve screenTime{screenName, kScreenColour, {}}, screenMemory{screenName, kScreenColour, {}};
    Curve exportTime{exportName, kExportColour, {}}, exportMemory{exportName, kExportColour, {}};
    // Exact edges: the same voxels (same time and memory), a better picture.
    // Its cost is in the trace, which the axes do not show: the subheading
    // says it.
    double slowest = 0.0, fastest = HUGE_VAL;
    for (const TradeRow& row : report.rows)
        if (row.exactEdges && row.traceMs > 0.0) {
            slowest = std::max(slowest, row.exactEdges->traceMs / row.traceMs);
            fastest = std::min(fastest, row.exactEdges->traceMs / row.traceMs);
        }
    std::string exactCost;
    if (slowest > 0.0)
        exactCost = "; exact edges trace in " +
                    (significant(fastest, 2) == significant(slowest, 2)
                         ? significant(fastest, 2)
                         : significant(fastest, 2) + " to " + significant(slowest, 2)) +
                    " times the voxels' time";
    const QString exactName = "Exact edges: depth error, p99";
    Curve exactTime{exactName, kExactColour, {}}, exactMemory{exactName, kExactColour, {}};
    for (const TradeRow& row : report.rows) {
        const QString label = QString::fromStdString(mm(row.featureSize) + " mm");
        const double depth = row.picture.depthMm.p99;
        const QString depthLabel = depth > 0.0 ? label : label + " (0)";
        screenTime.points.push_back({std::max(row.voxelizeMs, kSmallest), std::max(depth, kSmallest), depthLabel});
        screenMemory.points.push_back(
            {std::max(row.gpuBytes / 1e6, kSmallest), std::max(depth, kSmallest), depthLabel});
        if (row.exactEdges) {
            const double e = row.exactEdges->picture.depthMm.p99;
            const QString exactLabel = e > 0.0 ? label : label + " (0)";
            exactTime.points.push_back({std::max(row.voxelizeMs, kSmallest), std::max(e, kSmallest), exactLabel});
            exactMemory.points.push_back({std::max(row.gpuBytes / 1e6, kSmallest), std::max(e, kSmallest), exactLabel});
        }
        if (row.exported) {
            const double d = row.exported->distance.max;
            const QString distanceLabel = d > 0.0 ? label : label + " (0)";
            exportTime.points.push_back(
                {std::max(row.exported->meshMs, kSmallest), std::max(d, kSmallest), distanceLabel});
            exportMemory.points.push_back(
                {std::max(row.exported->stlBytes / 1e6, kSmallest), std::max(d, kSmallest), distanceLabel});
        }
    }
    std::vector<Curve> timeCurves{screenTime}, memoryCurves{screenMemory};
    if (!exactTime.points.empty()) {
        timeCurves.push_back(exactTime);
        memoryCurves.push_back(exactMemory);
    }
    const bool exported = !exportTime.points.empty();
    if (exported) {
        timeCurves.push_back(exportTime);
        memoryCurves.push_back(exportMemory);
    }

    QGraphicsScene scene;
    QChart* left =
        makePanel("Error against time",
                  exported ? "time (ms): cold voxelization (screen), meshing (export)" : "time (ms): cold voxelization",
                  timeCurves);
    QChart* right = makePanel("Error against memory",
                              exported ? "memory (MB): GPU voxel buffers (screen), binary STL (export)"
                                       : "memory (MB): GPU voxel buffers",
                              memoryCurves);
    scene.addItem(left);
    scene.addItem(right);
    left->setGeometry(0, kHeader, kPanelWidth, kPanelHeight);
    right->setGeometry(kPanelWidth, kHeader, kPanelWidth, kPanelHeight);
    auto* heading = scene.addSimpleText(QString::fromStdString("kerf bench: " + title + " - speed against accuracy"));
    QFont headingFont = heading->font();
    headingFont.setPointSize(17);
    headingFont.setBold(true);
    heading->setFont(headingFont);
    heading->setPos(20, 8);
    auto* subheading = scene.addSimpleText(
        QString::fromStdString("log scales, one point per feature size; " + std::to_string(report.width) + "x" +
                               std::to_string(report.height) + " " + report.view + " view traced on " + report.device +
                               "; " + std::to_string(report.threads) + " CPU threads" + exactCost));
    QFont subFont = subheading->font();
    subFont.setPointSize(10);
    subheading->setFont(subFont);
    subheading->setPos(22, 40);
    // Lay the charts out now (it is otherwise a posted event), so that
    // points map to positions.
    for (QChart* chart : {left, right})
        chart->layout()->activate();
    QCoreApplication::processEvents();
    labelPoints(left, timeCurves);
    labelPoints(right, memoryCurves);

    const QRectF area(0, 0, 2 * kPanelWidth, kHeader + kPanelHeight);
    scene.setSceneRect(area);
    QImage image(area.size().toSize(), QImage::Format_ARGB32);
    image.fill(Qt::white);
    {
        QPainter painter(&image);
        painter.setRenderHint(QPainter::Antialiasing);
        painter.setRenderHint(QPainter::TextAntialiasing);
        scene.render(&painter, area, area);
    }
    QByteArray bytes;
    QBuffer buffer(&bytes);
    buffer.open(QIODevice::WriteOnly);
    if (!image.save(&buffer, "PNG")) throw std::runtime_error(png.string() + ": Qt could not encode the plot as PNG");
    writeFileAtomically(png, std::string_view(bytes.constData(), std::size_t(bytes.size())));
}

} // namespace kerf
