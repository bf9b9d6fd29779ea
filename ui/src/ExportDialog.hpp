#pragma once
// Export: the file (.stl or .3mf: the format follows the extension), the
// feature size (cell edge; the document's by default), an optional
// tolerance (the mesh simplified and refined against the exact surface to
// that distance), binary or ASCII STL. Meshing and writing go through the
// core's exportPart(), as `kerf export` does, on a worker thread with a
// progress bar and a Cancel button; the file is written whole or not at
// all. The result line describes the file as a reader gets it back.
//
// The part exported is the document as it is when Export is pressed (the
// dialog does not block the main window: a newcomer hid a feature with the
// dialog open and got the part as it was when the dialog opened).

#include "kerf/document/Document.hpp"
#include "kerf/mesher/MeshPart.hpp"

#include <QDialog>

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

class QCheckBox;
class QLineEdit;
class QComboBox;
class QProgressBar;
class QPushButton;
class QLabel;
class QTimer;

namespace kerf::ui {

class QuantityEdit;

/// What a person chose in the dialog: MainWindow keeps the choices of the
/// last file written and opens the dialog with them again for the same
/// document (a newcomer found it back at ~/part.stl and 0.05 mm every time).
struct ExportChoices {
    std::filesystem::path file;
    int format = 0;                    // the format box's entry: binary STL, ASCII STL, 3MF
    std::optional<double> featureSize; // typed in; else the document's
    bool simplify = true;
    double tolerance = kDefaultExportTolerance;
};

struct ExportOutcome {
    bool written = false;
    bool cancelled = false;
    QString message; // the result or the reason it failed
    std::size_t triangles = 0; // as a reader of the file gets them
    bool closed = false;       // read back as a closed, oriented 2-manifold without crossings
    bool simplified = false;   // held to the tolerance (not the marching-cubes fallback)
};

class ExportDialog : public QDialog {
    Q_OBJECT
public:
    /// `document`: the part as it is now (asked when Export is pressed);
    /// `partName`: the name a 3MF file gives the object; `choices`: the
    /// fields as they open (the file suggested, or the last one written).
    ExportDialog(std::function<Document()> document, std::string partName, const ExportChoices& choices,
                 QWidget* parent = nullptr);
    ~ExportDialog() override;

    /// What is selected (asked when Export is pressed): "Only the selected
    /// feature" exports that feature alone, as the part places it.
    void setSelection(std::function<std::vector<std::string>()> selection);

    /// Starts the export with the dialog's settings (the Export button).
    void start();
    /// Asks a running export to stop (the Cancel button).
    void cancel();
    bool running() const { return worker_.joinable() && !finished_; }
    const ExportOutcome& outcome() const { return outcome_; }
    /// The fields as they are now.
    ExportChoices choices() const;

signals:
    void finished(const kerf::ui::ExportOutcome& outcome);

protected:
    void reject() override;

private:
    void poll();
    /// Keeps the format box and the file's extension in step.
    void formatChosen(int index);
    void pathEdited(const QString& text);
    /// Text typed in a number field that it could not read, and why ("" when none).
    void noteUnreadable(QuantityEdit* field, const QString& label, const QString& reason);
    /// Whether `file` may be written: it does not exist, it is the file this
    /// dialog wrote or the file dialog confirmed, or the person says Replace.
    bool mayReplace(const std::filesystem::path& file);
    /// The fields and Browse… take input (not while an export runs: a
    /// newcomer changed the tolerance mid-export and could not tell which
    /// one the file had).
    void setFieldsEnabled(bool enabled);

    std::function<Document()> document_;
    std::function<std::vector<std::string>()> selection_;
    std::string partName_;
    QString alone_; // what the running export takes alone, said ("" for the whole part)
    std::string aloneName_; // that feature's name, the 3MF object's
    Document doc_; // what the running export meshes (taken when Export is pressed)
    std::filesystem::path folder_; // where a file name typed without a folder goes
    double documentFeatureSize_ = 0.0; // what the feature size field opens with when none was typed
    std::filesystem::path wroteLast_, confirmed_; // replaced without asking again
    std::filesystem::path writtenTo_;             // the running export's file
    QString unreadable_; // the last number field's text that could not be read: refused at Export, once
    bool closeWhenDone_ = false; // closed while meshing: cancel, then close
    QLineEdit* path_;
    QuantityEdit* featureSize_;
    QCheckBox* simplify_;
    QCheckBox* onlySelection_;
    QuantityEdit* tolerance_;
    QComboBox* format_;
    QPushButton* browse_;
    QProgressBar* progress_;
    QLabel* result_;
    QPushButton* exportButton_;
    QPushButton* cancelButton_;
    QTimer* timer_;

    std::thread worker_;
    std::atomic<bool> cancel_{false};
    std::atomic<double> fraction_{0.0};
    std::atomic<bool> done_{false};
    bool finished_ = true;
    ExportOutcome outcome_, workerOutcome_;
};

} // namespace kerf::ui
