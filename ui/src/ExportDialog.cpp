#include "ExportDialog.hpp"

#include "QuantityEdit.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/AtomicFile.hpp"
#include "kerf/document/NodePlacement.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshFile.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/voxelizer/GridLayout.hpp"
#include "kerf/voxelizer/RequestBudget.hpp"

#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QLocale>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QTimer>
#include <QVBoxLayout>

#include <algorithm>
#include <cctype>
#include <initializer_list>
#include <iterator>
#include <chrono>
#include <new>

namespace kerf::ui {

namespace {

// The format box's entries, in this order.
constexpr MeshFileFormat kFormats[] = {MeshFileFormat::BinaryStl, MeshFileFormat::AsciiStl, MeshFileFormat::ThreeMf};

QString extensionOf(MeshFileFormat format) { return format == MeshFileFormat::ThreeMf ? ".3mf" : ".stl"; }

QString withExtension(const QString& path, MeshFileFormat format)
{
    const QString ext = extensionOf(format);
    if (path.endsWith(ext, Qt::CaseInsensitive)) return path;
    QString base = path;
    if (base.endsWith(".stl", Qt::CaseInsensitive) || base.endsWith(".3mf", Qt::CaseInsensitive)) base.chop(4);
    return base + ext;
}

QString megabytes(std::uint64_t bytes)
{
    return bytes < 1000000 ? QObject::tr("%1 kB").arg(double(bytes) / 1e3, 0, 'f', 1)
                           : QObject::tr("%1 MB").arg(double(bytes) / 1e6, 0, 'f', 1);
}

// What a reader of the file gets, in one paragraph.
QString describeWritten(const std::filesystem::path& file, MeshFileFormat format, const ExportedPart& exported,
                        double tolerance, double seconds, double ownFeatureSize, const Aabb& partBounds)
{
    const MeshReport& r = exported.report.asRead;
    const QLocale locale;
    QString s = QObject::tr("%1: %2 triangles, %3 (%4) in %5 s.")
                    .arg(QString::fromStdString(file.string()))
                    .arg(locale.toString(qulonglong(r.triangles)))
                    .arg(QString::fromUtf8(describe(format)))
                    .arg(megabytes(exported.report.bytes))
                    .arg(seconds, 0, 'f', 2);
    // In a woodworker's words: a closed, oriented 2-manifold is a closed
    // (watertight) solid; its components are pieces; its genus is the
    // number of holes through it (the side chair's nine openings).
    const int holes = r.genus().value_or(-1);
    const QString pieces = r.components == 1 ? QObject::tr("1 piece") : QObject::tr("%1 pieces").arg(r.components);
    const QString through = holes == 0   ? QObject::tr("no hole through it")
                            : holes == 1 ? QObject::tr("1 hole through it")
                            : holes > 1  ? QObject::tr("%1 holes through it").arg(holes)
                                         : QString();
    // A file that does not match the part says so first, before the
    // read-back's reassurances (a closed solid can still be the wrong one).
    const std::string miss = describeVisibleMiss(exported.stats, tolerance, ownFeatureSize);
    if (!miss.empty()) s += "\n" + QObject::tr("Warning: %1.").arg(QString::fromStdString(miss));
    s += "\n" + QObject::tr("As read back: closed (watertight), no crossing triangles; %1%2.")
                    .arg(pieces, through.isEmpty() ? QString() : ", " + through);
    if (!(tolerance > 0.0))
        s += "\n" + QObject::tr("Not simplified: every cell's triangles at %1 mm cells, not held to a tolerance.")
                        .arg(exported.stats.cellSize);
    if (tolerance > 0.0 && exported.simplificationDefects.empty() && exported.stats.trianglesOverTolerance == 0)
        s += "\n" + QObject::tr("Every triangle within %1 mm of the exact surface (worst sample %2 mm).")
                        .arg(tolerance)
                        .arg(exported.stats.worstSample, 0, 'g', 2);
    if (tolerance > 0.0 && exported.simplificationDefects.empty() && exported.stats.partSamples > 0) {
        const QString side = QString::fromStdString(describePartSide(exported.stats, tolerance));
        s += "\n" + side.left(1).toUpper() + side.mid(1) + ".";
    }
    if (!exported.simplificationDefects.empty())
        s += "\n" + QObject::tr("The mesh simplified to %1 mm had %2; the marching-cubes mesh at %3 mm was written "
                                "instead (closed, sharp edges kept, larger, not held to the tolerance).")
                        .arg(tolerance)
                        .arg(QString::fromStdString(exported.simplificationDefects))
                        .arg(exported.stats.cellSize);
    if (exported.stats.hiddenDetailCells > 0) {
        s += "\n" + QObject::tr("Warning: %1.").arg(QString::fromStdString(describeHiddenDetail(exported.stats, ownFeatureSize)));
    }
    if (exported.stats.trianglesOverTolerance > 0 && miss.empty()) {
        s += "\n" + QObject::tr("Warning: %1. The file is a closed solid all the same, within %2 mm of the part "
                                "(finer than a router or printer reproduces).")
                        .arg(QString::fromStdString(describeTrianglesOverTolerance(exported.stats, tolerance, ownFeatureSize)))
                        .arg(kVisibleMiss);
    } else if (exported.stats.trianglesOverTolerance > 0) {
        s += "\n" + QObject::tr("Warning: %1.")
                        .arg(QString::fromStdString(describeTrianglesOverTolerance(exported.stats, tolerance, ownFeatureSize)));
    }
    if (const std::string coarse = describeCoarseTolerance(exported.stats, tolerance); !coarse.empty())
        s += "\n" + QObject::tr("Warning: %1.").arg(QString::fromStdString(coarse));
    if (const std::string coarse =
            describeCoarseCoordinates(partBounds, format, exported.report.spacing, exported.report.offset, tolerance);
        !coarse.empty())
        s += "\n" + QObject::tr("Warning: %1.").arg(QString::fromStdString(coarse));
    if (!exported.stats.note.empty()) s += "\n" + QString::fromStdString(exported.stats.note);
    return s;
}

} // namespace

ExportDialog::ExportDialog(std::function<Document()> document, std::string partName, const ExportChoices& choices,
                           QWidget* parent)
    : QDialog(parent), document_(std::move(document)), partName_(std::move(partName)), doc_(document_()),
      folder_(choices.file.parent_path())
{
    const std::filesystem::path& suggested = choices.file;
    setWindowTitle(tr("Export"));
    setMinimumWidth(560); // room for a path and the result's sentences
    auto* layout = new QVBoxLayout(this);
    auto* form = new QFormLayout;
    auto* pathRow = new QWidget(this);
    auto* ph = new QHBoxLayout(pathRow);
    ph->setContentsMargins(0, 0, 0, 0);
    path_ = new QLineEdit(QString::fromStdString(suggested.string()), pathRow);
    path_->setObjectName("export.path");
    path_->setToolTip(tr("The file to write: .stl (STL) or .3mf (3MF)"));
    browse_ = new QPushButton(tr("Browse…"), pathRow);
    auto* browse = browse_;
    ph->addWidget(path_, 1);
    ph->addWidget(browse);
    form->addRow(tr("File"), pathRow);
    format_ = new QComboBox(this);
    format_->setObjectName("export.format");
    format_->addItem(tr("Binary STL"));
    format_->addItem(tr("ASCII STL"));
    format_->addItem(tr("3MF"));
    format_->setToolTip(tr("STL: what every slicer reads (float32 coordinates). 3MF: millimetres, the part's name, "
                           "exact to six decimals anywhere"));
    form->addRow(tr("Format"), format_);
    featureSize_ = new QuantityEdit(QuantityEdit::Unit::Millimetres, this);
    featureSize_->setObjectName("export.featureSize");
    const Tape tape = compileTape(doc_);
    documentFeatureSize_ = doc_.settings.featureSize.value_or(
        tape.bounds().isEmpty() || !tape.bounds().isBounded() ? 1.0 : defaultFeatureSize(tape.bounds()));
    featureSize_->setValue(choices.featureSize.value_or(documentFeatureSize_));
    featureSize_->setToolTip(tr("The smallest feature resolved: the edge of the marching-cubes cells. Sharp edges "
                                "and corners are kept at any size"));
    form->addRow(tr("Feature size"), featureSize_);
    auto* toleranceRow = new QWidget(this);
    auto* th = new QHBoxLayout(toleranceRow);
    th->setContentsMargins(0, 0, 0, 0);
    simplify_ = new QCheckBox(tr("Simplify to within"), toleranceRow);
    simplify_->setObjectName("export.simplify");
    simplify_->setToolTip(tr("Flat faces become a few large triangles and curved faces get as many as the "
                             "tolerance needs. Unticked: every cell's triangles (quicker, a much larger file)"));
    simplify_->setChecked(choices.simplify);
    tolerance_ = new QuantityEdit(QuantityEdit::Unit::Millimetres, toleranceRow);
    tolerance_->setObjectName("export.tolerance");
    tolerance_->setValue(choices.tolerance);
    tolerance_->setEnabled(choices.simplify);
    tolerance_->setToolTip(tr("The largest distance allowed between the mesh and the exact surface"));
    th->addWidget(simplify_);
    th->addWidget(tolerance_, 1);
    form->addRow(tr("Tolerance"), toleranceRow);
    // One board of a cabinet for the CNC, not the cabinet fused into one
    // solid (a newcomer's drawer).
    onlySelection_ = new QCheckBox(tr("Only the selected feature"), this);
    onlySelection_->setObjectName("export.onlySelection");
    onlySelection_->setToolTip(tr("The feature selected in the tree, with what it holds, where the part places it "
                                  "(every copy of an array or mirror above it)"));
    onlySelection_->setEnabled(false); // until the window says what is selected
    form->addRow(tr("Part"), onlySelection_);
    connect(simplify_, &QCheckBox::toggled, tolerance_, &QWidget::setEnabled);
    layout->addLayout(form);
    progress_ = new QProgressBar(this);
    progress_->setObjectName("export.progress");
    progress_->setRange(0, 1000);
    progress_->setValue(0);
    layout->addWidget(progress_);
    // The report (one line to a dozen) scrolls in room kept for it from the
    // start: a dialog that grew with each report moved its buttons, and a
    // newcomer's clicks on Close landed on nothing.
    result_ = new QLabel;
    result_->setObjectName("export.result");
    result_->setWordWrap(true);
    result_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    result_->setAlignment(Qt::AlignLeft | Qt::AlignTop);
    auto* resultArea = new QScrollArea(this);
    resultArea->setObjectName("export.resultArea");
    resultArea->setWidget(result_);
    resultArea->setWidgetResizable(true);
    resultArea->setFrameShape(QFrame::NoFrame);
    resultArea->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    resultArea->setMinimumHeight(12 * fontMetrics().lineSpacing());
    layout->addWidget(resultArea, 1);
    auto* buttons = new QDialogButtonBox(this);
    exportButton_ = buttons->addButton(tr("Export"), QDialogButtonBox::AcceptRole);
    exportButton_->setObjectName("export.start");
    cancelButton_ = buttons->addButton(QDialogButtonBox::Cancel);
    cancelButton_->setObjectName("export.dismiss");
    cancelButton_->setText(tr("Cancel"));
    layout->addWidget(buttons);
    connect(exportButton_, &QPushButton::clicked, this, &ExportDialog::start);
    connect(cancelButton_, &QPushButton::clicked, this, [this] {
        if (running()) cancel();
        else QDialog::reject();
    });
    connect(browse, &QPushButton::clicked, this, [this] {
        const QString stl = tr("STL files (*.stl)"), threeMf = tr("3MF files (*.3mf)");
        QString filter = format_->currentIndex() == 2 ? threeMf : stl;
        const QString f = QFileDialog::getSaveFileName(this, tr("Export"), path_->text(), stl + ";;" + threeMf,
                                                       &filter);
        if (f.isEmpty()) return;
        const bool asThreeMf = f.endsWith(".3mf", Qt::CaseInsensitive) ||
                               (!f.endsWith(".stl", Qt::CaseInsensitive) && filter == threeMf);
        const QString chosen = withExtension(f, asThreeMf ? MeshFileFormat::ThreeMf : MeshFileFormat::BinaryStl);
        // The file dialog asked already whether to replace a file it names
        // whole (not one whose extension was added here).
        if (chosen == f) confirmed_ = chosen.toStdString();
        path_->setText(chosen);
    });
    // Text a number field cannot read ("abc") is put back to the value
    // before it when the field is left, as the Export button is clicked:
    // say so, and refuse that click, rather than export the old value in
    // silence.
    connect(featureSize_, &QuantityEdit::unreadable, this,
            [this](const QString& why) { noteUnreadable(featureSize_, tr("Feature size"), why); });
    connect(tolerance_, &QuantityEdit::unreadable, this,
            [this](const QString& why) { noteUnreadable(tolerance_, tr("Tolerance"), why); });
    // Typed in again since ("xyz" left, then 0.3 typed over it): the refusal
    // was for text no longer there; the click exports what the field shows
    // (or is refused anew, when the new text reads as no number either).
    for (QuantityEdit* field : {featureSize_, tolerance_})
        connect(field->findChild<QLineEdit*>(), &QLineEdit::textEdited, this, [this] { unreadable_.clear(); });
    connect(format_, &QComboBox::currentIndexChanged, this, &ExportDialog::formatChosen);
    connect(path_, &QLineEdit::textChanged, this, &ExportDialog::pathEdited);
    format_->setCurrentIndex(std::clamp(choices.format, 0, int(std::size(kFormats)) - 1));
    pathEdited(path_->text());
    timer_ = new QTimer(this);
    timer_->setInterval(50);
    connect(timer_, &QTimer::timeout, this, &ExportDialog::poll);
}

void ExportDialog::setSelection(std::function<std::vector<std::string>()> selection)
{
    selection_ = std::move(selection);
    onlySelection_->setEnabled(bool(selection_));
}

ExportDialog::~ExportDialog()
{
    cancel_ = true;
    if (worker_.joinable()) worker_.join();
}

void ExportDialog::formatChosen(int index)
{
    const QString path = path_->text().trimmed();
    if (path.isEmpty()) return;
    const QString changed = withExtension(path, kFormats[index]);
    if (changed != path) path_->setText(changed);
}

void ExportDialog::pathEdited(const QString& text)
{
    // The extension decides; the box follows (ASCII stays ASCII for .stl).
    const QString t = text.trimmed();
    const QSignalBlocker block(format_);
    if (t.endsWith(".3mf", Qt::CaseInsensitive)) format_->setCurrentIndex(2);
    else if (t.endsWith(".stl", Qt::CaseInsensitive) && format_->currentIndex() == 2) format_->setCurrentIndex(0);
}

void ExportDialog::noteUnreadable(QuantityEdit* field, const QString& label, const QString& reason)
{
    unreadable_ = tr("%1: %2; the field shows %3 again. Nothing was exported.")
                      .arg(label, reason, field->textFromValue(field->value()) + " mm");
    result_->setText(unreadable_);
}

ExportChoices ExportDialog::choices() const
{
    ExportChoices c;
    c.file = path_->text().trimmed().toStdString();
    c.format = format_->currentIndex();
    if (featureSize_->value() != documentFeatureSize_) c.featureSize = featureSize_->value();
    c.simplify = simplify_->isChecked();
    c.tolerance = tolerance_->value();
    return c;
}

void ExportDialog::setFieldsEnabled(bool enabled)
{
    for (QWidget* w : std::initializer_list<QWidget*>{path_, browse_, format_, featureSize_, simplify_})
        w->setEnabled(enabled);
    tolerance_->setEnabled(enabled && simplify_->isChecked());
    onlySelection_->setEnabled(enabled && bool(selection_));
}

bool ExportDialog::mayReplace(const std::filesystem::path& file)
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return true; // new (or refused later, naming why)
    if (file == wroteLast_ || file == confirmed_) return true;
    QMessageBox ask(QMessageBox::Warning, tr("Replace file?"),
                    tr("%1 already exists.").arg(QString::fromStdString(file.string())), QMessageBox::NoButton, this);
    ask.setObjectName("export.replace");
    ask.setInformativeText(tr("Replace it with the part exported now? The file as it is will be lost."));
    QPushButton* replace = ask.addButton(tr("Replace"), QMessageBox::AcceptRole);
    replace->setObjectName("export.replace.yes");
    QPushButton* keep = ask.addButton(tr("Keep It"), QMessageBox::RejectRole);
    keep->setObjectName("export.replace.no");
    ask.setDefaultButton(keep); // Enter keeps the file: nothing is lost by a key pressed once too often
    ask.exec();
    if (ask.clickedButton() != replace) return false;
    confirmed_ = file;
    return true;
}

void ExportDialog::start()
{
    if (running()) return;
    if (worker_.joinable()) worker_.join();
    QString typed = path_->text().trimmed();
    // "~/parts/leg.stl", as a shell takes it.
    if (typed == "~" || typed.startsWith("~/")) typed = QDir::homePath() + typed.mid(1);
    std::filesystem::path file = typed.toStdString();
    // A bare name goes beside the suggested file (the document's folder, or
    // home), not into whatever folder the program was started from.
    if (!file.empty() && file.is_relative()) file = folder_ / file;
    auto refuse = [this](const QString& why) {
        outcome_ = ExportOutcome{};
        outcome_.message = why;
        result_->setText(why);
        progress_->setValue(0); // not the last export's, which this one is not
        emit finished(outcome_);
    };
    if (!unreadable_.isEmpty()) {
        const QString why = unreadable_;
        unreadable_.clear(); // the next click exports the value the field shows
        return refuse(why);
    }
    if (file.empty()) return refuse(tr("Choose a file to export to."));
    const double featureSize = featureSize_->value();
    if (!(featureSize > 0.0)) return refuse(tr("The feature size must be a positive number of millimetres."));
    const double tolerance = simplify_->isChecked() ? tolerance_->value() : 0.0;
    if (simplify_->isChecked() && !(tolerance > 0.0))
        return refuse(tr("The tolerance must be a positive number of millimetres (for the marching-cubes mesh without "
                         "simplification, untick Simplify)."));
    std::optional<MeshFileFormat> format = meshFileFormatFor(file, format_->currentIndex() == 1);
    if (!format) return refuse(tr("Name the file .stl (STL) or .3mf (3MF)."));
    if (!mayReplace(file))
        return refuse(tr("Not exported: %1 is kept as it was. Choose another name, or export again and answer "
                         "Replace.")
                          .arg(QString::fromStdString(file.string())));
    // The part as it is now, not as it was when the dialog opened; or the
    // feature selected now, alone.
    Document part = document_();
    alone_.clear();
    if (onlySelection_->isChecked()) {
        const std::vector<std::string> ids = selection_ ? selection_() : std::vector<std::string>{};
        const Node* n = ids.size() == 1 ? part.root.find(ids.front()) : nullptr;
        if (!n || n == &part.root)
            return refuse(tr("Not exported: select one feature in the tree to export it alone (%n selected), or "
                             "untick Only the selected feature.",
                             nullptr, int(ids.size())));
        alone_ = QString::fromStdString(edit::describeFeatureAlone(part, n->id));
        aloneName_ = n->name.value_or(n->id);
        part = edit::documentOfNodeAlone(part, n->id);
    }
    doc_ = std::move(part);
    cancel_ = false;
    done_ = false;
    fraction_ = 0.0;
    finished_ = false;
    exportButton_->setEnabled(false);
    setFieldsEnabled(false);
    cancelButton_->setText(tr("Cancel")); // stops the export
    result_->setText(tr("Meshing…"));
    progress_->setValue(0);
    timer_->start();
    const std::string partName = !alone_.isEmpty() ? aloneName_ : partName_.empty() ? file.stem().string() : partName_;
    writtenTo_ = file;
    worker_ = std::thread([this, file, featureSize, tolerance, format = *format, partName] {
        ExportOutcome o;
        try {
            // What cannot be done is refused before any meshing (issue 14):
            // an output that is not a regular file, a mesh this machine
            // cannot afford. On this thread: the estimate takes up to a
            // couple of seconds.
            checkOutputFile(file);
            const Tape tape = compileTape(doc_);
            // (The default on a part far from the origin is written, with
            // the warning the result gives; a tolerance typed in is refused.)
            if (const auto why = tolerance != kDefaultExportTolerance
                                     ? toleranceTheFileCannotHold(tape.bounds(), format, tolerance)
                                     : partTheFileCannotHold(tape.bounds(), format)) {
                std::string sentence = *why;
                sentence[0] = char(std::toupper(static_cast<unsigned char>(sentence[0])));
                o.message = tr("Not exported: %1.").arg(QString::fromStdString(sentence));
                workerOutcome_ = o;
                done_ = true;
                return;
            }
            const RequestCost cost = estimateRequest(tape, featureSize, meshRequestKind(tolerance));
            if (const auto over = overBudget(cost, RequestBudget::forThisMachine(), featureSize)) {
                o.message = tr("Not exported: meshing at %1").arg(QString::fromStdString(*over));
                workerOutcome_ = o;
                done_ = true;
                return;
            }
            MeshOptions options;
            options.featureSize = featureSize;
            // The default where the file cannot hold it: the finest it holds.
            const double meshTolerance =
                tolerance == kDefaultExportTolerance ? defaultToleranceFor(tape.bounds(), format) : tolerance;
            options.tolerance = meshTolerance;
            const Progress progress([this](double f) { fraction_ = f; }, [this] { return cancel_.load(); });
            const auto t0 = std::chrono::steady_clock::now();
            const ExportedPart exported = exportPart(doc_, options, file, format, partName, progress);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (exported.cancelled) {
                o.cancelled = true;
                o.message = tr("Cancelled; nothing was written.");
            } else if (exported.empty) {
                // With the thinnest detail found and the feature size that
                // resolves it, as kerf export says (a newcomer at 1000 mm
                // was told only that the part was empty).
                std::string sentence = describeEmptyPart(exported.stats, tape.bounds());
                sentence[0] = char(std::toupper(static_cast<unsigned char>(sentence[0])));
                o.message = tr("%1; nothing was written.").arg(QString::fromStdString(sentence));
            } else if (!exported.report.solid()) {
                o.message =
                    tr("Not exported: %1.").arg(QString::fromStdString(describeNotWritten(exported, format)));
            } else {
                o.written = true;
                o.closed = true;
                o.triangles = exported.report.asRead.triangles;
                o.simplified = meshTolerance > 0.0 && exported.simplificationDefects.empty();
                o.message = describeWritten(file, format, exported, meshTolerance, seconds, documentFeatureSize_,
                                            tape.bounds());
                if (meshTolerance != tolerance)
                    o.message += "\n" + tr("Warning: the default tolerance of %1 mm is finer than this file holds for "
                                           "this part: meshed to %2 mm, the finest it holds.")
                                         .arg(tolerance)
                                         .arg(meshTolerance, 0, 'g', 2);
                // A hole moved off its board: the file lacks it, as the part does.
                if (const std::string idle = describeToolsCuttingNothing(doc_); !idle.empty())
                    o.message += "\n" + tr("Warning: %1.").arg(QString::fromStdString(idle));
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
    if (outcome_.written) {
        progress_->setValue(1000);
        wroteLast_ = writtenTo_;
    } else {
        // A newcomer read a bar left at 98% under "Not exported" as an
        // export nearly done; nothing was written, as a refusal shows.
        progress_->setValue(0);
    }
    setFieldsEnabled(true);
    if (!alone_.isEmpty() && outcome_.written)
        outcome_.message = tr("%1, where the part places it.\n").arg(alone_) + outcome_.message;
    result_->setText(outcome_.message);
    exportButton_->setEnabled(true);
    // Nothing runs any more: the button only closes the dialog (a newcomer
    // read "Cancel" under a written file as "the file will be taken back").
    cancelButton_->setText(tr("Close"));
    emit finished(outcome_);
    if (closeWhenDone_) QDialog::reject();
}

void ExportDialog::reject()
{
    // Closing the dialog while meshing cancels the export, and the dialog
    // closes once it has stopped (within a fraction of a second).
    if (running()) {
        closeWhenDone_ = true;
        cancel();
        return;
    }
    QDialog::reject();
}

} // namespace kerf::ui
