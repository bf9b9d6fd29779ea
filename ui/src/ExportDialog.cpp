#include "ExportDialog.hpp"

#include "QuantityEdit.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/mesher/StlWriter.hpp"
#include "kerf/document/AtomicFile.hpp"
#include "kerf/voxelizer/GridLayout.hpp"
#include "kerf/voxelizer/RequestBudget.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

#include <QComboBox>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QTimer>
#include <QVBoxLayout>

#include <chrono>
#include <new>

namespace kerf::ui {

ExportDialog::ExportDialog(const Document& doc, const std::filesystem::path& suggested, QWidget* parent)
    : QDialog(parent), doc_(doc)
{
    setWindowTitle(tr("Export STL"));
    auto* layout = new QVBoxLayout(this);
    auto* form = new QFormLayout;
    auto* pathRow = new QWidget(this);
    auto* ph = new QHBoxLayout(pathRow);
    ph->setContentsMargins(0, 0, 0, 0);
    path_ = new QLineEdit(QString::fromStdString(suggested.string()), pathRow);
    path_->setObjectName("export.path");
    auto* browse = new QPushButton(tr("Browse…"), pathRow);
    ph->addWidget(path_, 1);
    ph->addWidget(browse);
    form->addRow(tr("File"), pathRow);
    featureSize_ = new QuantityEdit(QuantityEdit::Unit::Millimetres, this);
    featureSize_->setObjectName("export.featureSize");
    const Tape tape = compileTape(doc_);
    featureSize_->setValue(doc_.settings.featureSize.value_or(
        tape.bounds().isEmpty() || !tape.bounds().isBounded() ? 1.0 : defaultFeatureSize(tape.bounds())));
    featureSize_->setToolTip(tr("Edge of the marching-cubes cells: smaller is more accurate, slower and larger"));
    form->addRow(tr("Feature size"), featureSize_);
    format_ = new QComboBox(this);
    format_->setObjectName("export.format");
    format_->addItem(tr("Binary STL"));
    format_->addItem(tr("ASCII STL"));
    form->addRow(tr("Format"), format_);
    layout->addLayout(form);
    progress_ = new QProgressBar(this);
    progress_->setRange(0, 1000);
    progress_->setValue(0);
    layout->addWidget(progress_);
    result_ = new QLabel(this);
    result_->setObjectName("export.result");
    result_->setWordWrap(true);
    layout->addWidget(result_);
    auto* buttons = new QDialogButtonBox(this);
    exportButton_ = buttons->addButton(tr("Export"), QDialogButtonBox::AcceptRole);
    exportButton_->setObjectName("export.start");
    cancelButton_ = buttons->addButton(QDialogButtonBox::Cancel);
    layout->addWidget(buttons);
    connect(exportButton_, &QPushButton::clicked, this, &ExportDialog::start);
    connect(cancelButton_, &QPushButton::clicked, this, [this] {
        if (running()) cancel();
        else QDialog::reject();
    });
    connect(browse, &QPushButton::clicked, this, [this] {
        const QString f = QFileDialog::getSaveFileName(this, tr("Export STL"), path_->text(), tr("STL files (*.stl)"));
        if (!f.isEmpty()) path_->setText(f.endsWith(".stl", Qt::CaseInsensitive) ? f : f + ".stl");
    });
    timer_ = new QTimer(this);
    timer_->setInterval(50);
    connect(timer_, &QTimer::timeout, this, &ExportDialog::poll);
}

ExportDialog::~ExportDialog()
{
    cancel_ = true;
    if (worker_.joinable()) worker_.join();
}

void ExportDialog::start()
{
    if (running()) return;
    if (worker_.joinable()) worker_.join();
    const std::filesystem::path file = path_->text().trimmed().toStdString();
    if (file.empty()) {
        result_->setText(tr("Choose a file to export to."));
        return;
    }
    const double featureSize = featureSize_->value();
    if (!(featureSize > 0.0)) {
        result_->setText(tr("The feature size must be a positive number of millimetres."));
        return;
    }
    const StlFormat format = format_->currentIndex() == 1 ? StlFormat::Ascii : StlFormat::Binary;
    cancel_ = false;
    done_ = false;
    fraction_ = 0.0;
    finished_ = false;
    exportButton_->setEnabled(false);
    result_->setText(tr("Meshing…"));
    progress_->setValue(0);
    timer_->start();
    worker_ = std::thread([this, file, featureSize, format] {
        ExportOutcome o;
        try {
            // What cannot be done is refused before any meshing (issue 14):
            // an output that is not a regular file, a mesh this machine
            // cannot afford. On this thread: the estimate takes up to a
            // couple of seconds.
            checkOutputFile(file);
            const RequestCost cost = estimateRequest(compileTape(doc_), featureSize, RequestKind::Mesh);
            if (const auto over = overBudget(cost, RequestBudget::forThisMachine(), featureSize)) {
                o.message = tr("Not exported: meshing at %1").arg(QString::fromStdString(*over));
                workerOutcome_ = o;
                done_ = true;
                return;
            }
            MeshOptions options;
            options.featureSize = featureSize;
            MeshProgress progress;
            progress.onProgress = [this](double f) { fraction_ = f; };
            progress.cancelled = [this] { return cancel_.load(); };
            MeshStats stats;
            const auto t0 = std::chrono::steady_clock::now();
            std::optional<Mesh> mesh = meshPart(doc_, options, progress, &stats);
            if (!mesh) {
                o.cancelled = true;
                o.message = tr("Cancelled; nothing was written.");
            } else if (mesh->triangles.empty()) {
                o.message = tr("The part is empty; nothing was written.");
            } else {
                const MeshReport report = checkMesh(*mesh);
                writeStl(*mesh, file, format);
                const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                o.written = true;
                o.triangles = mesh->triangles.size();
                o.closed = report.watertight();
                o.message = tr("%1: %L2 triangles in %3 s; %4")
                                .arg(QString::fromStdString(file.filename().string()))
                                .arg(qulonglong(o.triangles))
                                .arg(seconds, 0, 'f', 2)
                                .arg(o.closed ? tr("closed, consistently oriented 2-manifold")
                                              : tr("NOT closed: check the part"));
                if (!stats.note.empty()) o.message += "\n" + QString::fromStdString(stats.note);
            }
        } catch (const std::bad_alloc&) {
            o.message = tr("Export failed: out of memory; choose a larger feature size.");
        } catch (const std::exception& e) {
            o.message = tr("Export failed: %1").arg(QString::fromUtf8(e.what()));
        }
        workerOutcome_ = o;
        done_ = true;
    });
}

void ExportDialog::cancel() { cancel_ = true; }

void ExportDialog::poll()
{
    progress_->setValue(int(fraction_.load() * 1000.0));
    if (!done_) return;
    timer_->stop();
    worker_.join();
    finished_ = true;
    outcome_ = workerOutcome_;
    if (outcome_.written) progress_->setValue(1000);
    result_->setText(outcome_.message);
    exportButton_->setEnabled(true);
    emit finished(outcome_);
}

void ExportDialog::reject()
{
    // Closing the dialog while meshing cancels the export first.
    if (running()) {
        cancel();
        return;
    }
    QDialog::reject();
}

} // namespace kerf::ui
