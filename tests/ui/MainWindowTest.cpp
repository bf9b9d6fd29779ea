// Scripted UI tests of the desktop application (QtTest), run under Xvfb with
// the xcb platform, the real main window and the Vulkan viewport on
// lavapipe: a part built from nothing through the UI, undo and redo of every
// step, save and reopen, refused values, crash recovery, tile-exact
// re-voxelization after an edit, viewport pictures, export, cut list,
// measure, section, and the CPU fallback.

#include "CutListDialog.hpp"
#include "ExportDialog.hpp"
#include "FeatureTreeModel.hpp"
#include "MainWindow.hpp"
#include "ParametersPanel.hpp"
#include "PropertyEditor.hpp"
#include "QuantityEdit.hpp"
#include "SelectionGhosts.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/Voxelize.hpp"
#include "kerf/mesher/MeshCheck.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/mesher/StlWriter.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"
#include "support/MeshFileReader.hpp"


#include <QAction>
#include <QApplication>
#include <QMap>
#include <QMessageBox>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QCheckBox>
#include <QElapsedTimer>
#include <QFile>
#include <QFileInfo>
#include <QMimeData>
#include <QPainter>
#include <QPushButton>
#include <QRegularExpression>
#include <QProgressBar>
#include <QComboBox>
#include <QCompleter>
#include <QAbstractItemView>
#include <QLabel>
#include <QLineEdit>
#include <QSettings>
#include <QDockWidget>
#include <QSignalSpy>
#include <QSlider>
#include <QTimer>
#include <QPointer>
#include <QStatusBar>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>
#include <QToolBar>
#include <QToolButton>
#include <QTreeView>
#include <QWheelEvent>
#include <QWindow>

#include <glm/glm.hpp>

#include <filesystem>
#include <memory>

// Under AddressSanitizer, llvmpipe's JIT-compiled pipelines leak by
// design (not Kerf's code): leak detection is off in this binary only.
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }

using namespace kerf;
using namespace kerf::ui;

namespace {

// Generous: under AddressSanitizer on two shared cores, lavapipe frames take seconds.
constexpr int kVoxelTimeoutMs = 300000;

std::unique_ptr<MainWindow> makeWindow(const QString& recoveryDir, MainWindowOptions options = {},
                                       bool rememberLayout = false)
{
    options.recoveryFolder = recoveryDir.toStdString();
    options.rememberLayout = rememberLayout; // by default each scenario starts from the default layout
    options.autosaveMs = 3600 * 1000; // the tests autosave by hand
    // The CPU voxelizer unless a scenario asks for the GPU (the setting is
    // remembered between runs).
    if (!options.voxelizeOnGpu) options.voxelizeOnGpu = false;
    if (!options.askSave) options.askSave = [](const QString&) { return QMessageBox::Discard; };
    if (!options.askRestore) options.askRestore = [](const RecoveryCandidate&) { return false; };
    if (!options.reportError) options.reportError = [](const QString&, const QString&) {}; // no modal boxes
    if (!options.askConfirm) options.askConfirm = [](const QString&) { return true; };
    auto w = std::make_unique<MainWindow>(std::move(options));
    w->resize(1280, 800);
    w->show();
    return w;
}

QAction* action(QWidget* w, const QString& name)
{
    QAction* a = w->findChild<QAction*>(name);
    if (!a) qFatal("no action %s", qPrintable(name));
    return a;
}

QuantityEdit* field(MainWindow& w, const QString& key)
{
    return w.propertyEditor()->findChild<QuantityEdit*>("field." + key);
}

// Types an expression into a field and presses Enter, as a person would.
void typeInto(QuantityEdit* edit, const QString& text)
{
    QVERIFY(edit);
    edit->setFocus();
    edit->selectAll();
    QTest::keyClicks(edit, text);
    QTest::keyClick(edit, Qt::Key_Return);
}

// Clicks the button named `button` in the next modal message box that
// shows while it lives (exec() runs its own event loop, where the timer
// fires), and keeps the box's text.
class MessageBoxAnswerer {
public:
    explicit MessageBoxAnswerer(QString button) : button_(std::move(button))
    {
        timer_.setInterval(20);
        QObject::connect(&timer_, &QTimer::timeout, [this] {
            auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget());
            if (!box) return;
            QPushButton* b = box->findChild<QPushButton*>(button_);
            if (!b) return;
            timer_.stop();
            text_ = box->text() + " " + box->informativeText();
            answered_ = true;
            b->click();
        });
        timer_.start();
    }
    bool answered() const { return answered_; }
    const QString& text() const { return text_; }

private:
    QTimer timer_;
    QString button_, text_;
    bool answered_ = false;
};

// Clicks a row of the feature tree (ctrl-click adds to the selection).
void clickRow(MainWindow& w, const std::string& id, Qt::KeyboardModifiers mods = {})
{
    const QModelIndex i = w.featureModel()->indexOf(id);
    QVERIFY2(i.isValid(), id.c_str());
    w.featureTree()->scrollTo(i);
    const QRect r = w.featureTree()->visualRect(i);
    // Right of the check box and the decoration.
    QTest::mouseClick(w.featureTree()->viewport(), Qt::LeftButton, mods, QPoint(r.right() - 8, r.center().y()));
}

// Writes `bytes` to `path` (a document, a file that is none); false if it cannot.
bool writeTestFile(const QString& path, const QByteArray& bytes)
{
    QFile f(path);
    return f.open(QIODevice::WriteOnly) && f.write(bytes) == bytes.size();
}

// Opens a bundled example and its export dialog, as File > Export does; null if either fails.
ExportDialog* openExportDialog(MainWindow& w, const char* example)
{
    if (!w.openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / example)) return nullptr;
    action(&w, "action.export")->trigger();
    return w.findChild<ExportDialog*>("exportDialog");
}

// Waits until the voxelizer has published, at full depth, the document as it is now.
bool waitForVoxels(MainWindow& w)
{
    const std::uint64_t revision = w.voxelizer()->lastSubmitted();
    return QTest::qWaitFor(
        [&] {
            const auto s = w.voxelizer()->latest();
            return s && s->documentRevision >= revision && s->complete;
        },
        kVoxelTimeoutMs);
}

// Waits until the viewport shows that publication.
bool waitForViewport(MainWindow& w)
{
    if (!waitForVoxels(w)) return false;
    const std::uint64_t version = w.voxelizer()->latest()->version;
    return QTest::qWaitFor(
        [&] {
            const auto s = w.viewport()->status();
            return s.shownVersion >= version && !s.streaming;
        },
        kVoxelTimeoutMs);
}

// Waits until the viewport shows a complete GPU build newer than `afterVersion`
// and the GPU voxelizer has nothing newer under way.
bool waitForGpuVoxels(MainWindow& w, std::uint64_t afterVersion)
{
    return QTest::qWaitFor(
        [&] {
            const auto s = w.viewport()->status();
            return s.gpuVoxels && s.shownComplete && !s.gpuBusy && s.shownVersion > afterVersion;
        },
        kVoxelTimeoutMs);
}

// Fraction of pixels that are not the background (the part, the grid lines
// excluded by comparing against a picture of the empty scene's colours:
// background pixels are grey-blue, the wood tone is orange).
double woodFraction(const QImage& image)
{
    std::size_t wood = 0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
            const QColor c = image.pixelColor(x, y);
            if (c.red() > c.blue() + 30) ++wood;
        }
    return double(wood) / double(image.width() * image.height());
}

double pictureDifference(const QImage& a, const QImage& b)
{
    if (a.size() != b.size()) return 1.0;
    std::size_t differ = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const QColor p = a.pixelColor(x, y), q = b.pixelColor(x, y);
            if (std::abs(p.red() - q.red()) + std::abs(p.green() - q.green()) + std::abs(p.blue() - q.blue()) > 24)
                ++differ;
        }
    return double(differ) / double(a.width() * a.height());
}

// Drops `data` on the window as a drag would: enter, then drop.
void drop(MainWindow& w, const QMimeData& data)
{
    const QPointF at(w.width() / 2.0, w.height() / 2.0);
    QDragEnterEvent enter(at.toPoint(), Qt::CopyAction, &data, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(&w, &enter);
    QVERIFY(enter.isAccepted());
    QDropEvent dropped(at, Qt::CopyAction, &data, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(&w, &dropped);
}

// The viewport's drawing surface, as a person's mouse and keyboard reach
// it: the Vulkan window, or the CPU tracer's widget.
struct Surface {
    qt::ViewportWidget* view = nullptr;
    QWindow* window = nullptr;

    explicit Surface(qt::ViewportWidget* v) : view(v)
    {
        for (QWindow* win : QGuiApplication::allWindows())
            if (win->surfaceType() == QSurface::VulkanSurface && win->isVisible()) window = win;
    }
    QWidget* widget(QPoint at) const { return view->childAt(at); }
    void click(QPoint at) const
    {
        if (window) QTest::mouseClick(window, Qt::LeftButton, Qt::NoModifier, at);
        else QTest::mouseClick(widget(at), Qt::LeftButton, Qt::NoModifier, at);
    }
    void press(QPoint at) const
    {
        if (window) QTest::mousePress(window, Qt::LeftButton, Qt::NoModifier, at);
        else QTest::mousePress(widget(at), Qt::LeftButton, Qt::NoModifier, at);
    }
    void move(QPoint at) const
    {
        if (window) QTest::mouseMove(window, at);
        else QTest::mouseMove(widget(at), at);
    }
    void release(QPoint at) const
    {
        if (window) QTest::mouseRelease(window, Qt::LeftButton, Qt::NoModifier, at);
        else QTest::mouseRelease(widget(at), Qt::LeftButton, Qt::NoModifier, at);
    }
    void keys(const QString& text) const
    {
        if (!window) {
            QTest::keyClicks(view->childAt(view->rect().center()), text);
            return;
        }
        for (const QChar c : text) QTest::keyClick(window, c.toLatin1());
    }
    void key(Qt::Key k) const
    {
        if (window) QTest::keyClick(window, k);
        else QTest::keyClick(view->childAt(view->rect().center()), k);
    }
    // Where a world point is in the view (logical pixels).
    QPoint at(const glm::dvec3& p) const
    {
        const auto px = view->camera().project(p);
        const glm::dvec2 one = view->devicePixel(QPointF(1, 0)) - view->devicePixel(QPointF(0, 0));
        return px ? QPoint(int(std::lround(px->x / one.x)), int(std::lround(px->y / one.x))) : QPoint(-1, -1);
    }
};

// The bookshelf side seen square on its drilled face (+X), close up on the
// first two shelf-pin holes (centres at y 37, z 160 and 192).
void lookAtTheFirstHoles(qt::ViewportWidget& v)
{
    v.setStandardView("right");
    ViewController close = v.view();
    // About 60 mm tall: a millimetre is ten pixels or so.
    close.fit(Aabb{glm::dvec3(8, 22, 152), glm::dvec3(10, 52, 200)}, double(v.width()) / v.height());
    v.setView(close);
}

// The bookshelf side open and in view, close up on its first holes, with
// the shelf-pin hole selected (its gizmo on the first copy); null if the
// file or its voxels fail.
qt::ViewportWidget* selectTheFirstShelfPinHole(MainWindow& w)
{
    if (!w.openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side.kerf") || !waitForViewport(w))
        return nullptr;
    qt::ViewportWidget* v = w.viewport();
    lookAtTheFirstHoles(*v);
    clickRow(w, "shelf-pin-hole");
    return v;
}

void saveScreenshot(MainWindow& w, const QString& name)
{
    const QString dir = qEnvironmentVariable("KERF_SCREENSHOT_DIR");
    if (dir.isEmpty()) return;
    const QImage frame = w.viewport()->grabFrame();
    QPixmap shot = w.grab(); // the widgets; the Vulkan child is painted in from its own frame
    QPainter p(&shot);
    p.drawImage(QRect(w.viewport()->mapTo(&w, QPoint(0, 0)), w.viewport()->size()), frame);
    p.end();
    shot.save(dir + "/" + name + ".png");
}

// A dialog or panel as the user sees it, for looking at (KERF_SCREENSHOT_DIR).
void saveWidgetShot(QWidget& widget, const QString& name)
{
    const QString dir = qEnvironmentVariable("KERF_SCREENSHOT_DIR");
    if (!dir.isEmpty()) widget.grab().save(dir + "/" + name + ".png");
}

} // namespace

class MainWindowTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase()
    {
        // Settings and data in folders of this process alone, not the one
        // folder of Qt's test mode: ctest runs the tests as processes side
        // by side, and one test's View > Lengths In > Inches reached the
        // fields of another ("R (in)" where "R (mm)" was due). Set before
        // anything reads a setting (QSettings keeps the folder it found).
        QVERIFY(home_.isValid());
        for (const char* variable : {"XDG_CONFIG_HOME", "XDG_DATA_HOME", "XDG_CACHE_HOME", "XDG_STATE_HOME"})
            qputenv(variable, (home_.path() + "/" + variable).toLocal8Bit());
        QVERIFY(recovery_.isValid());
        QVERIFY(files_.isValid());
    }

    void buildsAPartFromNothingWithUndoRedoAndSaves();
    void refusesBadValuesBesideTheFieldAndChangesNothing();
    void expressionsAndMergedSteps();
    void restoresTheAutosaveAfterACrash();
    void reVoxelizesOnlyTheTilesTheEditReaches();
    void viewportShowsThePartAndChangesAfterAnEdit();
    void brickRendererDrawsTheSamePartAndStepsAsideWhereItCannot();
    void exportDialogWritesAClosedMesh();
    void exportDialogNamesWhatTheToleranceMissed();
    void exportDialogNamesTheFormatThatHoldsAFarPart();
    void exportDialogSaysWhenTheFileDoesNotMatchThePart();
    void exportDialogSaysWhereDetailHidesBetweenTheCells();
    void exportDialogTakesThePartAsItIsWhenExportIsPressed();
    void exportDialogExportsTheSelectedFeatureAlone();
    void exportDialogAsksBeforeReplacingAFileAndOpensWithTheLastChoices();
    void everyShortcutIsBoundOnceAndRedoAnswersBothKeys();
    void theWheelEditsOnlyTheFieldBeingEdited();
    void ctrlZRightAfterTypingAValueUndoesIt();
    void theToolbarKeepsItsButtonsWhereTheyAre();
    void aBundledExampleOpensAsAnUntitledCopy();
    void undoStepsAndMessagesSpeakThePanelsLanguage();
    void unreadableTextIsSaidUnderItsFieldAndOlderMessagesGo();
    void aStatusMessageGetsTheWholeBar();
    void theSectionKeepsATypedOffsetAndTheSliderFollowsIt();
    void theViewsFeatureSizeIsSetWithNothingSelected();
    void theLayoutIsRememberedAndTheViewFollowsThePartsScale();
    void anOperationFromTheToolbarActsOnTheSelectedFeature();
    void theTreeMarksTheBaseAndAsksBeforeAToolGoesAboveIt();
    void deletingWhatADifferenceCutsFromAsksFirst();
    void cutListMeasureAndSection();
    void refusedFilesChangeNothing();
    void dragAndDropRegroupsInTheTree();
    void modelsOnlyWhatTheViewNeedsWithinTheBudget();
    void keepsWhatThePartHidesCoarseUntilItShows();
    void promptsBeforeChangesAreLost();
    void dropsDocumentsAndMeshesOntoTheWindow();
    void aClickOnThePartSelectsItsFeature();
    void measuringSnapsToHoleCentresAndDrawsTheDimension();
    void keyFiveInTheViewMovesTheOrthographicCheckMark();
    void theViewKeysAnswerWithTheFeatureTreeInFocus();
    void aPartThinnerThanAVoxelEverywhereIsSaidNotLeftBlank();
    void aNewBoxStaysOnTheGridWhateverSetsItsHeight();
    void escapeInAFieldTakesBackWhatWasTyped();
    void aNewPartIsSavedWithItsParametersBeforeItsFirstFeature();
    void aFileThatIsNoKerfDocumentIsRefusedBeforeAskingToSave();
    void aMisspeltFieldIsNamedOnOpening();
    void deletingAMirroredLegTakesTheEmptiedMirrorAlong();
    void aMirrorTurnsToAnotherAxisInOneClick();
    void theGizmoLeavesACoordinateSetByAnExpression();
    void theGizmoMovesAHoleBySnappedOrTypedDistancesInOneUndoStep();
    void aSelectedHoleShowsItsToolBodyAsAGhost();
    void theBoundingBoxOfTheSelectionIsMeasuredAndDrawn();
    void aTurnedProfileIsEditedInItsPointTable();
    void aProfilePointFollowsAParameter();
    void theThicknessChangedInTheParametersPanelCarriesEveryDependentFeature();
    void aRefusedFormulaOpensAgainToMend();
    void deleteInTheParametersTableIsTheParametersNotTheFeatures();
    void lengthsShownInInchesAreTypedInInchesAndTheDocumentKeepsMillimetres();
    void theGpuVoxelizesWhenAskedAndTheCpuTakesOverWhenItCannot();

private:
    QTemporaryDir home_, recovery_, files_;
};

void MainWindowTest::buildsAPartFromNothingWithUndoRedoAndSaves()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    QVERIFY(w->session()->document().root.children.empty());

    // Add a box and size it through the property editor: it rests on the
    // grid, and stays there as it is made 18 mm thick.
    action(w.get(), "action.add.box")->trigger();
    QCOMPARE(w->selectedNodeIds(), std::vector<std::string>{"box"});
    typeInto(field(*w, "size.x"), "600");
    typeInto(field(*w, "size.y"), "300");
    typeInto(field(*w, "size.z"), "18");
    // Add a cylinder (it goes beside the box: a box takes no children).
    action(w.get(), "action.add.cylinder")->trigger();
    QCOMPARE(w->selectedNodeIds(), std::vector<std::string>{"cylinder"});
    typeInto(field(*w, "radius"), "4");
    typeInto(field(*w, "height"), "40");
    typeInto(field(*w, "translate.x"), "100");
    // Both under a difference: click the box, ctrl-click the cylinder, group.
    clickRow(*w, "box");
    clickRow(*w, "cylinder", Qt::ControlModifier);
    QCOMPARE(w->selectedNodeIds(), (std::vector<std::string>{"box", "cylinder"}));
    action(w.get(), "action.group.difference")->trigger();

    const Document built = w->session()->document();
    const Document expected = Document::parse(R"({"format":"kerf","version":1,"root":
        {"id":"root","type":"union","name":"Part","children":[
          {"id":"difference","type":"difference","children":[
            {"id":"box","type":"box","size":[600,300,18],"transform":{"translate":[0,0,9]}},
            {"id":"cylinder","type":"cylinder","radius":4,"height":40,"transform":{"translate":[100,0,20]}}]}]}})",
                                              "expected.kerf");
    QCOMPARE(QString::fromStdString(built.serialize()), QString::fromStdString(expected.serialize()));
    QVERIFY(w->isWindowModified());

    // Undo every step back to the empty part, then redo them all.
    QUndoStack* stack = w->session()->undoStack();
    const int steps = stack->count();
    QCOMPARE(steps, 9); // add, 3 sizes, add, radius, height, x, group
    std::vector<std::string> states;
    for (int i = 0; i < steps; ++i) {
        states.push_back(w->session()->document().serialize());
        action(w.get(), "action.undo")->trigger();
    }
    QVERIFY(w->session()->document().root.children.empty());
    for (int i = steps - 1; i >= 0; --i) {
        action(w.get(), "action.redo")->trigger();
        QCOMPARE(QString::fromStdString(w->session()->document().serialize()),
                 QString::fromStdString(states[std::size_t(i)]));
    }
    QVERIFY(w->session()->document() == built);

    // Save, reopen in a new window, compare.
    const std::filesystem::path file = (files_.path() + "/built.kerf").toStdString();
    QVERIFY(w->saveAs(file));
    QVERIFY(!w->isWindowModified());
    auto other = makeWindow(recovery_.path());
    QVERIFY(other->openFile(file));
    QVERIFY(other->session()->document() == built);
    QCOMPARE(other->windowTitle(), QString("built.kerf[*] — Kerf"));
}

void MainWindowTest::refusesBadValuesBesideTheFieldAndChangesNothing()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.cylinder")->trigger();
    const Document before = w->session()->document();
    const int undoBefore = w->session()->undoStack()->count();

    typeInto(field(*w, "radius"), "-5");
    QVERIFY(w->session()->document() == before);
    QCOMPARE(w->session()->undoStack()->count(), undoBefore);
    // In the panel's words: the row's label and the feature as the tree
    // names it, not the file's "node 'cylinder', field 'radius'" (a
    // newcomer did not know what those were).
    QCOMPARE(w->propertyEditor()->errorFor("radius"), QString("Radius of the cylinder: must be > 0, not -5"));
    QCOMPARE(field(*w, "radius")->value(), 10.0); // the document's value again
    auto* name = w->propertyEditor()->findChild<QLineEdit*>("field.name");
    QVERIFY(name);
    name->setFocus();
    QTest::keyClicks(name, "Pin hole");
    QTest::keyClick(name, Qt::Key_Return);
    QCOMPARE(w->session()->document().root.find("cylinder")->name, std::optional<std::string>("Pin hole"));
    // The panel's title follows the rename (it kept the id).
    const auto* title = w->propertyEditor()->findChild<QLabel*>("properties.title");
    QVERIFY(title);
    QCOMPARE(title->text(), QString("Cylinder — Pin hole"));
    typeInto(field(*w, "radius"), "-2.5");
    QCOMPARE(w->propertyEditor()->errorFor("radius"), QString("Radius of Pin hole: must be > 0, not -2.5"));

    // A round larger than half the box: refused, and said why.
    action(w.get(), "action.add.box")->trigger();
    typeInto(field(*w, "round"), "15");
    QCOMPARE(w->propertyEditor()->errorFor("round"), QString("Round of the box: must be <= half the smallest size (10), not 15"));
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().round, 0.0);

    // Text that is no number at all: said so, nothing changes.
    const Document now = w->session()->document();
    typeInto(field(*w, "round"), "18*");
    QVERIFY(w->session()->document() == now);
    QVERIFY2(!w->propertyEditor()->errorFor("round").isEmpty(), "an unreadable value is reported");

    // A valid value clears the message.
    typeInto(field(*w, "round"), "2");
    QCOMPARE(w->propertyEditor()->errorFor("round"), QString());
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().round, 2.0);

    // Two selected: said so, not "Nothing selected — the part" (a newcomer
    // with three rows selected read that), and no field of either to edit.
    w->selectNodes({"cylinder", "box"});
    QCOMPARE(title->text(), QString("2 features selected"));
    QVERIFY(!w->propertyEditor()->findChild<QuantityEdit*>("field.radius") ||
            !w->propertyEditor()->findChild<QuantityEdit*>("field.radius")->isVisible());
    w->selectNodes({"box"});
    QCOMPARE(title->text(), QString("Box — box"));
    w->selectNodes({});
    QCOMPARE(title->text(), QString("Nothing selected — the part"));
}

void MainWindowTest::expressionsAndMergedSteps()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    typeInto(field(*w, "size.x"), "18*2");
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, 36.0);
    typeInto(field(*w, "size.y"), "(300 + 2) / 2 mm");
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.y, 151.0);
    // Stepping a value with the arrow keys (as dragging does) merges into one undo step.
    const int count = w->session()->undoStack()->count();
    QuantityEdit* z = field(*w, "size.z");
    z->setFocus();
    for (int i = 0; i < 5; ++i) QTest::keyClick(z, Qt::Key_Up);
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.z, 25.0);
    QCOMPARE(w->session()->undoStack()->count(), count + 1);
    action(w.get(), "action.undo")->trigger();
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.z, 20.0);
    // Values typed and entered one after another are a step each (a
    // newcomer typed 510, then 520, and one undo went back past both).
    typeInto(field(*w, "size.x"), "510");
    typeInto(field(*w, "size.x"), "520");
    action(w.get(), "action.undo")->trigger();
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, 510.0);
    action(w.get(), "action.undo")->trigger();
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, 36.0);

    // A refused number typed over a field an expression drives: the field
    // shows the expression again, as before the typing (it showed the
    // number, and a newcomer thought the expression gone).
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side-parametric.kerf"));
    w->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(w.get())); // the focus is the active window's
    clickRow(*w, "panel");
    QuantityEdit* thickness = field(*w, "size.x");
    typeInto(thickness, "-5");
    QVERIFY(thickness->hasFocus());
    QVERIFY2(!w->propertyEditor()->errorFor("size.x").isEmpty(), "the refusal is said");
    QCOMPARE(thickness->findChild<QLineEdit*>()->text(), QString("=thickness"));
    QCOMPARE(w->session()->document().root.find("panel")->expressions.at("size[0]"), std::string("thickness"));
}

void MainWindowTest::restoresTheAutosaveAfterACrash()
{
    QTemporaryDir folder;
    Document left;
    {
        auto w = makeWindow(folder.path());
        action(w.get(), "action.new")->trigger();
        action(w.get(), "action.add.sphere")->trigger();
        typeInto(field(*w, "radius"), "42");
        w->autosaveNow();
        typeInto(field(*w, "radius"), "43"); // after the last autosave: lost with the crash
        left = w->session()->document();
        w->recovery().abandon(); // the process "dies": no clean shutdown
    }
    QCOMPARE(left.root.find("sphere")->as<SphereParams>().radius, 43.0);

    MainWindowOptions options;
    int asked = 0;
    options.askRestore = [&](const RecoveryCandidate& c) {
        ++asked;
        return !c.original; // an unsaved part
    };
    auto w = makeWindow(folder.path(), options);
    w->offerRecovery();
    QCOMPARE(asked, 1);
    const Node* sphere = w->session()->document().root.find("sphere");
    QVERIFY(sphere);
    QCOMPARE(sphere->as<SphereParams>().radius, 42.0); // the last autosave
    QVERIFY(w->session()->isModified());
    // Offered once: the files are gone.
    w->offerRecovery();
    QCOMPARE(asked, 1);

    // A second crash before the restored work is saved: it is offered again.
    w->recovery().abandon();
    w.reset();
    std::optional<double> offered;
    options.askRestore = [&](const RecoveryCandidate& c) {
        const Document d = RecoveryStore::load(c);
        if (const Node* s = d.root.find("sphere")) offered = s->as<SphereParams>().radius;
        return false;
    };
    auto again = makeWindow(folder.path(), options);
    again->offerRecovery();
    QVERIFY2(offered.has_value(), "the restored work was lost with the second crash");
    QCOMPARE(*offered, 42.0);
}

void MainWindowTest::reVoxelizesOnlyTheTilesTheEditReaches()
{
    auto w = makeWindow(recovery_.path());
    const std::filesystem::path file = std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side.kerf";
    QVERIFY(w->openFile(file));
    QVERIFY(waitForVoxels(*w));
    const auto before = w->voxelizer()->latest();
    const Document oldDoc = w->session()->document();

    // Move the toe-kick notch 10 mm along Y through the property editor.
    w->selectNodes({"toe-kick"});
    QuantityEdit* y = field(*w, "translate.y");
    typeInto(y, QString::number(y->value() + 10.0));
    const Document newDoc = w->session()->document();
    QVERIFY(!(newDoc == oldDoc));
    QVERIFY(waitForVoxels(*w));
    const auto after = w->voxelizer()->latest();
    QVERIFY(after->layout == before->layout);

    // Every tile the notch's old or new place cannot reach (grown by two
    // voxel diagonals) keeps its very data; the rebuilt ones are few.
    const GridLayout& g = after->layout;
    const double margin = 2.0 * std::sqrt(3.0) * g.voxelSize + 1e-6;
    const Aabb oldBox = worldBoundsOfNodes(oldDoc).at("toe-kick").grown(margin);
    const Aabb newBox = worldBoundsOfNodes(newDoc).at("toe-kick").grown(margin);
    std::size_t changed = 0, reachable = 0;
    for (long i = 0; i < g.tileCount(); ++i) {
        const Aabb tile = g.tileBox(g.tileCoord(i));
        const bool reached = tile.overlaps(oldBox) || tile.overlaps(newBox);
        reachable += reached;
        if (before->tiles[std::size_t(i)] != after->tiles[std::size_t(i)]) {
            ++changed;
            QVERIFY2(reached, qPrintable(QString("tile %1 was rebuilt outside the edit's reach").arg(i)));
        }
    }
    QVERIFY(changed > 0);
    QVERIFY(reachable < std::size_t(g.tileCount()) / 4);
    QCOMPARE(w->voxelizer()->lastStats().dirtyTiles <= reachable, true);
}

void MainWindowTest::viewportShowsThePartAndChangesAfterAnEdit()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf"));
    QVERIFY(waitForViewport(*w));
    const QImage first = w->viewport()->grabFrame();
    QVERIFY(!first.isNull());
    QVERIFY2(woodFraction(first) > 0.05, "the chair fills part of the picture");
    saveScreenshot(*w, "app-side-chair");

    // Make the seat 200 mm deeper: the picture changes once the new voxels are shown.
    w->selectNodes({"seat"});
    QuantityEdit* x = field(*w, "size.x");
    typeInto(x, QString::number(x->value() + 200.0));
    QVERIFY(waitForViewport(*w));
    const QImage second = w->viewport()->grabFrame();
    QVERIFY2(pictureDifference(first, second) > 0.01, "the picture shows the edit");

    // A standard view, with the selection highlighted.
    action(w.get(), "action.view.front")->trigger();
    const QImage front = w->viewport()->grabFrame();
    QVERIFY(pictureDifference(second, front) > 0.05);
    // Exact edges (the hybrid refinement) on: still a picture, still no validation error.
    action(w.get(), "action.exactEdges")->trigger();
    // On lavapipe beside a busy machine (CI's other builds) the exact
    // picture once took longer than the 10 s default: a slow frame is not
    // what this checks.
    const QImage exact = w->viewport()->grabFrame(60000);
    QVERIFY(!exact.isNull());
    QVERIFY(woodFraction(exact) > 0.05);
    const auto status = w->viewport()->status();
    QVERIFY(status.frames > 0);
    QVERIFY(!status.device.isEmpty());
    QVERIFY2(status.validationErrors == 0, qPrintable(status.lastValidationMessage));
    if (qEnvironmentVariableIsSet("KERF_NO_VULKAN")) {
        QVERIFY(!status.vulkan);
        QVERIFY(status.fallbackReason.contains("KERF_NO_VULKAN"));
        QVERIFY(w->findChild<QLabel*>("status.device")->text().contains("CPU reference tracer"));
    } else {
        QVERIFY2(status.vulkan, qPrintable(status.fallbackReason));
    }
}

// View > Brick Renderer: the same part drawn by the brick renderer once its
// bricks are made, the status saying so; a section plane the bricks cut as
// the tracer does (the same picture, caps and all); Exact Edges (which the
// bricks do not draw) hands the part back to the tracer, and turning it off
// back to the bricks.
void MainWindowTest::brickRendererDrawsTheSamePartAndStepsAsideWhereItCannot()
{
    if (qEnvironmentVariableIsSet("KERF_NO_VULKAN")) QSKIP("the brick renderer needs Vulkan");
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "stool.kerf"));
    QVERIFY(waitForViewport(*w));
    const QImage traced = w->viewport()->grabFrame();
    QVERIFY(!w->viewport()->status().bricks);
    const std::size_t tracedBytes = w->viewport()->status().voxelBytes;
    auto* frame = w->findChild<QLabel*>("status.frame");
    action(w.get(), "action.brickRenderer")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(w->viewport()->status().bricks, kVoxelTimeoutMs);
    QTRY_VERIFY(frame->text().contains("bricks"));
    const QImage bricks = w->viewport()->grabFrame();
    QVERIFY(!bricks.isNull());
    QVERIFY(woodFraction(bricks) > 0.05);
    QVERIFY2(pictureDifference(traced, bricks) < 0.01, "the bricks draw the tracer's picture");
    // A section through the seat, seen by the tracer and then by the bricks.
    auto* sectionOn = w->findChild<QCheckBox*>("section.enabled");
    action(w.get(), "action.brickRenderer")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(!w->viewport()->status().bricks, kVoxelTimeoutMs);
    sectionOn->setChecked(true);
    QVERIFY(w->viewport()->section().enabled);
    QTRY_VERIFY2_WITH_TIMEOUT(pictureDifference(traced, w->viewport()->grabFrame()) > 0.01,
                              "the section changes the picture", kVoxelTimeoutMs);
    const QImage tracedCut = w->viewport()->grabFrame();
    action(w.get(), "action.brickRenderer")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(w->viewport()->status().bricks, kVoxelTimeoutMs);
    QTRY_VERIFY(frame->text().contains("bricks"));
    const QImage bricksCut = w->viewport()->grabFrame();
    saveScreenshot(*w, "brick-renderer-section");
    QVERIFY2(pictureDifference(tracedCut, bricksCut) < 0.01, "the bricks cut as the tracer cuts");
    sectionOn->setChecked(false);
    action(w.get(), "action.exactEdges")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(!w->viewport()->status().bricks, kVoxelTimeoutMs);
    QTRY_VERIFY(frame->text().contains("trace"));
    action(w.get(), "action.exactEdges")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(w->viewport()->status().bricks, kVoxelTimeoutMs);
    // The bricks' memory counts while they are there, and goes with them.
    const std::size_t withBricks = w->viewport()->status().voxelBytes;
    QVERIFY(withBricks > 2 * tracedBytes);
    action(w.get(), "action.brickRenderer")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(!w->viewport()->status().bricks, kVoxelTimeoutMs);
    QTRY_COMPARE(w->viewport()->status().voxelBytes, tracedBytes);
    const auto status = w->viewport()->status();
    QVERIFY2(status.validationErrors == 0, qPrintable(status.lastValidationMessage));
}

// A part the export cannot hold to its tolerance: the report says how many
// triangles stay beyond it, where the worst is and (as the miss is one a
// woodworker would see) the feature size to try,
// never "every triangle within", and the dialog grows to show it whole.
void MainWindowTest::exportDialogNamesWhatTheToleranceMissed()
{
    // Two boards touching along an edge: where their edges meet, 1 mm cells
    // leave triangles beyond 0.1 mm that no split mends (issue 13, open;
    // when that is mended this scenario needs another part that misses).
    const QString doc = files_.path() + "/touching.kerf";
    {
        QFile f(doc);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","children":[
            {"id":"a","type":"box","size":[20,20,18],"transform":{"translate":[-10,-10,0]}},
            {"id":"b","type":"box","size":[20,20,18],"transform":{"translate":[10,10,0]}}]}})");
    }
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(doc.toStdString()));
    action(w.get(), "action.export")->trigger();
    auto* dialog = w->findChild<ExportDialog*>("exportDialog");
    QVERIFY(dialog);
    dialog->findChild<QLineEdit*>("export.path")->setText(files_.path() + "/touching.stl");
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(1.0);
    dialog->findChild<QCheckBox*>("export.simplify")->setChecked(true);
    dialog->findChild<QuantityEdit*>("export.tolerance")->setValue(0.1);
    QSignalSpy done(dialog, &ExportDialog::finished);
    QTest::mouseClick(dialog->findChild<QPushButton*>("export.start"), Qt::LeftButton);
    QVERIFY(done.wait(300000));
    const QString message = dialog->outcome().message;
    QVERIFY2(dialog->outcome().written, qPrintable(message));
    QVERIFY2(dialog->outcome().simplified, qPrintable(message));
    QVERIFY2(message.contains("beyond the tolerance of 0.1 mm (the worst at ("), qPrintable(message));
    // One feature size to try, the same in every sentence that advises one
    // (the part's own here: the document sets none, and the dialog opened
    // at the size the part's extent gives): the file misses the part by
    // 0.2 mm, which the warning that the file does not match it says with
    // the size; the sentence on the triangles over the tolerance names none
    // and does not call finer cells no cure.
    QStringList advised;
    for (const auto& m : QRegularExpression("feature size of ([0-9.]+ mm)").globalMatch(message)) advised << m.captured(1);
    QVERIFY2(!advised.isEmpty() && advised.count(advised.front()) == advised.size(), qPrintable(message));
    QVERIFY2(message.contains("the file does not match the part"), qPrintable(message));
    QVERIFY2(!message.contains("no sure cure"), qPrintable(message));
    QVERIFY2(!message.contains("Every triangle within"), qPrintable(message));
    auto* result = dialog->findChild<QLabel*>("export.result");
    QTRY_VERIFY2(result->height() >= result->heightForWidth(result->width()), qPrintable(message));
    saveWidgetShot(*dialog, "export-dialog-tolerance-missed");
}

// A newcomer exported a 10 mm ball standing 10 km from the origin as STL at
// its 0.25 mm cells: float32 steps by 1 mm there, the file would not be a
// solid, and the dialog says why and what holds it, its bar back at 0 (it
// stood at 98% under "Not exported"); chosen as 3MF, the same part is
// written and reads back closed.
void MainWindowTest::exportDialogNamesTheFormatThatHoldsAFarPart()
{
    const QString doc = files_.path() + "/far-ball.kerf";
    QVERIFY(writeTestFile(doc, R"({"format":"kerf","version":1,"settings":{"feature_size":0.25},)"
                               R"("root":{"id":"ball","type":"sphere","radius":5,"transform":{"translate":[1e7,0,0]}}})"));
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(doc.toStdString()));
    action(w.get(), "action.export")->trigger();
    auto* dialog = w->findChild<ExportDialog*>("exportDialog");
    QVERIFY(dialog);
    const QString stl = files_.path() + "/far-ball.stl";
    dialog->findChild<QLineEdit*>("export.path")->setText(stl);
    QSignalSpy done(dialog, &ExportDialog::finished);
    QTest::mouseClick(dialog->findChild<QPushButton*>("export.start"), Qt::LeftButton);
    QVERIFY(done.wait(300000));
    const QString refused = dialog->outcome().message;
    QVERIFY2(!dialog->outcome().written, qPrintable(refused));
    QVERIFY2(refused.startsWith("Not exported: a reader of the file would not get a closed solid") &&
                 refused.contains("the file's coordinates step by 1 mm where the part reaches, too coarse for cells "
                                  "of 0.25 mm; a .3mf file keeps the detail"),
             qPrintable(refused));
    QVERIFY(!QFile::exists(stl));
    QCOMPARE(dialog->findChild<QProgressBar*>("export.progress")->value(), 0);
    saveWidgetShot(*dialog, "export-dialog-far-part-as-stl");

    dialog->findChild<QComboBox*>("export.format")->setCurrentText("3MF");
    const QString threeMf = dialog->findChild<QLineEdit*>("export.path")->text();
    QCOMPARE(threeMf, files_.path() + "/far-ball.3mf");
    QTest::mouseClick(dialog->findChild<QPushButton*>("export.start"), Qt::LeftButton);
    QVERIFY(done.wait(300000));
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));
    QCOMPARE(dialog->findChild<QProgressBar*>("export.progress")->value(), 1000);
    const MeshReport report = checkMesh(test::readMeshFile(threeMf.toStdString()));
    QVERIFY(report.watertight());
    QCOMPARE(report.components, std::size_t(1));
    saveWidgetShot(*dialog, "export-dialog-far-part-as-3mf");
}

// A newcomer exported a shelf side at 10 mm cells: its pin holes came out
// through the show face, 3.4 mm off, and the result ended "The file is a
// closed solid all the same". The table top at 8 mm cells (its own are
// 1 mm) misses its groove by 1.3 mm: said first, with the size to use.
void MainWindowTest::exportDialogSaysWhenTheFileDoesNotMatchThePart()
{
    auto w = makeWindow(recovery_.path());
    ExportDialog* dialog = openExportDialog(*w, "table-top.kerf");
    QVERIFY(dialog);
    dialog->findChild<QLineEdit*>("export.path")->setText(files_.path() + "/table-top-coarse.stl");
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(8.0);
    // The buttons stay where they were whatever the report's length (a
    // dialog that grew with it moved them from under a newcomer's pointer).
    auto* close = dialog->findChild<QPushButton*>("export.dismiss");
    QVERIFY(QTest::qWaitForWindowExposed(dialog));
    const QSize sizeBefore = dialog->size();
    const QPoint closeBefore = close->mapTo(dialog, QPoint(0, 0));
    QSignalSpy done(dialog, &ExportDialog::finished);
    QTest::mouseClick(dialog->findChild<QPushButton*>("export.start"), Qt::LeftButton);
    QVERIFY(done.wait(120000));
    const QString message = dialog->outcome().message;
    QVERIFY2(dialog->outcome().written, qPrintable(message));
    QTest::qWait(50); // any resize the report would cause
    QCOMPARE(dialog->size(), sizeBefore);
    QCOMPARE(close->mapTo(dialog, QPoint(0, 0)), closeBefore);
    QVERIFY(message.count('\n') >= 4); // a long report, then
    const qsizetype miss = message.indexOf("Warning: the file does not match the part: in places it is up to ");
    QVERIFY2(miss > 0, qPrintable(message));
    QVERIFY2(miss < message.indexOf("As read back"), qPrintable(message)); // said before the reassurances
    QVERIFY2(message.contains("export it at a feature size of 1 mm (the part's own)"), qPrintable(message));
    QVERIFY2(!message.contains("all the same"), qPrintable(message));
}

void MainWindowTest::exportDialogSaysWhereDetailHidesBetweenTheCells()
{
    // The bookshelf side at 4 mm cells: the 1 mm of panel between the toe
    // kick and the bottom dado lies between lattice points.
    auto w = makeWindow(recovery_.path());
    ExportDialog* dialog = openExportDialog(*w, "bookshelf-side.kerf");
    QVERIFY(dialog);
    dialog->findChild<QLineEdit*>("export.path")->setText(files_.path() + "/side.stl");
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(4.0);
    dialog->findChild<QCheckBox*>("export.simplify")->setChecked(false); // the warning, not the simplification
    QSignalSpy done(dialog, &ExportDialog::finished);
    QTest::mouseClick(dialog->findChild<QPushButton*>("export.start"), Qt::LeftButton);
    QVERIFY(done.wait(120000));
    const QString message = dialog->outcome().message;
    QVERIFY2(dialog->outcome().written, qPrintable(message));
    QVERIFY2(message.contains("Warning: material 1 mm thin at ("), qPrintable(message));
    // The part's own 1 mm resolves 1 mm of material (a lattice plane lies
    // inside it), and is what the report advises, once.
    QVERIFY2(message.contains("it is missing from the mesh or in pieces; a feature size of 1 mm (the part's own) "
                              "resolves it."),
             qPrintable(message));
}

void MainWindowTest::exportDialogExportsTheSelectedFeatureAlone()
{
    // A newcomer's drawer came out of the 3MF as one fused solid; the CNC
    // wanted one board. The table top's slab alone has no mortises: more
    // volume than the whole part.
    auto w = makeWindow(recovery_.path());
    ExportDialog* dialog = openExportDialog(*w, "table-top.kerf");
    QVERIFY(dialog);
    auto* only = dialog->findChild<QCheckBox*>("export.onlySelection");
    QVERIFY(only && only->isEnabled() && !only->isChecked());
    // 8 mm cells: the mortises still show in the volume (about 91,000 mm^3
    // of the slab's), at half the time of 4 mm, which took this scenario
    // past QtTest's 300 s under ASan on a slow machine.
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(8.0);
    QSignalSpy done(dialog, &ExportDialog::finished);
    const auto exportTo = [&](const QString& name) {
        dialog->findChild<QLineEdit*>("export.path")->setText(files_.path() + "/" + name);
        const qsizetype before = done.count();
        QTest::mouseClick(dialog->findChild<QPushButton*>("export.start"), Qt::LeftButton);
        return done.count() > before || done.wait(120000); // a refusal finishes at once
    };
    QVERIFY(exportTo("whole.3mf"));
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));
    const double whole = checkMesh(test::readMeshFile((files_.path() + "/whole.3mf").toStdString())).volume;

    // Nothing selected: refused, saying what to do.
    only->setChecked(true);
    w->selectNodes({});
    QVERIFY(exportTo("nothing.3mf"));
    QVERIFY(!dialog->outcome().written);
    QVERIFY2(dialog->outcome().message.contains("select one feature in the tree"), qPrintable(dialog->outcome().message));

    w->selectNodes({"top-slab"});
    QVERIFY(exportTo("slab.3mf"));
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));
    QVERIFY2(dialog->outcome().message.startsWith("Top alone"), qPrintable(dialog->outcome().message));
    const MeshReport slab = checkMesh(test::readMeshFile((files_.path() + "/slab.3mf").toStdString()));
    QVERIFY(slab.watertight());
    QCOMPARE(slab.components, std::size_t(1));
    QVERIFY2(slab.volume > whole + 1000.0, qPrintable(QString("%1 against %2").arg(slab.volume).arg(whole)));
}

// What a newcomer met (2026-11-28): the dialog does not block the main
// window, and it exported the part as it was when it opened (a feature
// hidden afterwards was still in the file); Export… again stacked a second
// dialog on the first; "abc" typed in a number field was put back to the
// old value and the export ran with it, saying nothing.
void MainWindowTest::exportDialogTakesThePartAsItIsWhenExportIsPressed()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    action(w.get(), "action.export")->trigger();
    auto* dialog = w->findChild<ExportDialog*>("exportDialog");
    QVERIFY(dialog);
    action(w.get(), "action.export")->trigger();
    QCOMPARE(w->findChildren<ExportDialog*>().size(), qsizetype(1));

    // Edited with the dialog open: the file has the box as it is now.
    typeInto(field(*w, "size.x"), "36");
    const glm::dvec3 size = w->session()->document().root.find("box")->as<BoxParams>().size;
    QCOMPARE(size.x, 36.0);
    const QString out = files_.path() + "/box.stl";
    dialog->findChild<QLineEdit*>("export.path")->setText(out);
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(2.0);
    QSignalSpy done(dialog, &ExportDialog::finished);
    auto* start = dialog->findChild<QPushButton*>("export.start");
    QTest::mouseClick(start, Qt::LeftButton);
    QVERIFY(done.wait(120000));
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));
    const MeshReport box = checkMesh(test::readMeshFile(out.toStdString()));
    QVERIFY(box.watertight());
    QVERIFY2(std::abs(box.volume - size.x * size.y * size.z) < 1e-3 * size.x * size.y * size.z,
             qPrintable(QString::number(box.volume)));
    // The message names the file with its folder.
    QVERIFY2(dialog->outcome().message.startsWith(out + ":"), qPrintable(dialog->outcome().message));

    // "abc" in the tolerance, then the Export button clicked (the field
    // left): refused, naming the text; the field shows its value again, and
    // the next click exports that.
    dialog->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(dialog));
    auto* tolerance = dialog->findChild<QuantityEdit*>("export.tolerance");
    tolerance->setFocus();
    tolerance->selectAll();
    QTest::keyClicks(tolerance, "abc");
    start->setFocus(); // as the click on the button takes the focus
    QTest::mouseClick(start, Qt::LeftButton);
    QCOMPARE(done.size(), 2);
    QVERIFY(!dialog->outcome().written);
    const QString refused = dialog->outcome().message;
    QVERIFY2(refused.startsWith("Tolerance: ") && refused.contains("'abc'") && refused.contains("Nothing was exported"),
             qPrintable(refused));
    QCOMPARE(tolerance->value(), kDefaultExportTolerance);
    QTest::mouseClick(start, Qt::LeftButton);
    QVERIFY(done.wait(120000));
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));

    // "xyz" left for another field, then 0.3 typed over it: the click
    // exports 0.3 mm (a newcomer was refused for the "xyz" no longer there).
    tolerance->setFocus();
    tolerance->selectAll();
    QTest::keyClicks(tolerance, "xyz");
    dialog->findChild<QuantityEdit*>("export.featureSize")->setFocus(); // as Tab does
    QCOMPARE(tolerance->value(), kDefaultExportTolerance);
    tolerance->setFocus();
    tolerance->selectAll();
    QTest::keyClicks(tolerance, "0.3");
    start->setFocus();
    QCOMPARE(tolerance->value(), 0.3);
    QTest::mouseClick(start, Qt::LeftButton);
    QVERIFY(done.wait(120000));
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));

    // Cells far larger than the box: nothing to write, and the feature size
    // that resolves it is named (it was only "the part is empty").
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(1000.0);
    QTest::mouseClick(start, Qt::LeftButton);
    QVERIFY(done.wait(120000));
    const QString empty = dialog->outcome().message;
    QVERIFY(!dialog->outcome().written);
    QVERIFY2(empty.contains("The part is empty at a feature size of 1000 mm") &&
                 empty.contains("a feature size of 5 mm (a quarter of its smallest extent or less) meshes it"),
             qPrintable(empty));
}

// A newcomer's session: a typed path replaced an existing file without a
// word, the fields could be changed while the export ran (which value had
// the file?), and the dialog opened at ~/part.stl and 0.05 mm every time.
void MainWindowTest::exportDialogAsksBeforeReplacingAFileAndOpensWithTheLastChoices()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    action(w.get(), "action.export")->trigger();
    QPointer<ExportDialog> dialog = w->findChild<ExportDialog*>("exportDialog");
    QVERIFY(dialog);
    const QString out = files_.path() + "/precious.stl";
    {
        QFile f(out);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write("the customer's file");
    }
    auto contents = [&] {
        QFile f(out);
        return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray();
    };
    dialog->findChild<QLineEdit*>("export.path")->setText(out);
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(2.0);
    dialog->findChild<QCheckBox*>("export.simplify")->setChecked(false);
    QSignalSpy done(dialog.data(), &ExportDialog::finished);
    auto* start = dialog->findChild<QPushButton*>("export.start");

    // Asked, and kept: nothing written, and the result says so.
    {
        MessageBoxAnswerer keep("export.replace.no");
        QTest::mouseClick(start, Qt::LeftButton);
        QVERIFY(keep.answered());
        QVERIFY2(keep.text().contains(out + " already exists") && keep.text().contains("will be lost"),
                 qPrintable(keep.text()));
    }
    QCOMPARE(done.size(), 1);
    QVERIFY(!dialog->outcome().written);
    QVERIFY2(dialog->outcome().message.contains("kept as it was"), qPrintable(dialog->outcome().message));
    QCOMPARE(contents(), QByteArray("the customer's file"));

    // Asked, and replaced; while it runs, the fields wait.
    {
        MessageBoxAnswerer replace("export.replace.yes");
        QTest::mouseClick(start, Qt::LeftButton);
        QVERIFY(replace.answered());
    }
    for (const char* name : {"export.path", "export.featureSize", "export.simplify", "export.format"})
        QVERIFY2(!dialog->findChild<QWidget*>(name)->isEnabled(), name);
    QVERIFY(done.wait(120000));
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));
    QVERIFY(dialog->findChild<QLineEdit*>("export.path")->isEnabled());
    QVERIFY(!dialog->findChild<QuantityEdit*>("export.tolerance")->isEnabled()); // still unticked
    QVERIFY(checkMesh(test::readMeshFile(out.toStdString())).watertight());
    // In words a woodworker reads: a closed piece without holes through it.
    QVERIFY2(dialog->outcome().message.contains("As read back: closed (watertight), no crossing triangles; 1 piece, "
                                                "no hole through it."),
             qPrintable(dialog->outcome().message));

    // The file this dialog wrote is written again without asking (a person
    // exporting, changing, exporting again); a box would be answered Keep.
    {
        MessageBoxAnswerer unexpected("export.replace.no");
        QTest::mouseClick(start, Qt::LeftButton);
        QVERIFY(done.wait(120000));
        QVERIFY(!unexpected.answered());
    }
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));

    // Closed and opened again: the file, the feature size and the
    // simplification as they were when the file was written.
    dialog->close();
    QTRY_VERIFY(!dialog);
    action(w.get(), "action.export")->trigger();
    dialog = w->findChild<ExportDialog*>("exportDialog");
    QVERIFY(dialog);
    QCOMPARE(dialog->findChild<QLineEdit*>("export.path")->text(), out);
    QCOMPARE(dialog->findChild<QuantityEdit*>("export.featureSize")->value(), 2.0);
    QVERIFY(!dialog->findChild<QCheckBox*>("export.simplify")->isChecked());
    QVERIFY(!dialog->findChild<QuantityEdit*>("export.tolerance")->isEnabled());
    // A new dialog asks again before replacing that file.
    {
        MessageBoxAnswerer keep("export.replace.no");
        QSignalSpy again(dialog.data(), &ExportDialog::finished);
        QTest::mouseClick(dialog->findChild<QPushButton*>("export.start"), Qt::LeftButton);
        QVERIFY(keep.answered());
        QCOMPARE(again.size(), 1);
        QVERIFY(!dialog->outcome().written);
    }
    dialog->close();
}

void MainWindowTest::everyShortcutIsBoundOnceAndRedoAnswersBothKeys()
{
    auto w = makeWindow(recovery_.path());
    // Every key of every action, once: Qt ignores a key bound twice (an
    // "ambiguous shortcut"), which is how Redo lost both of its keys.
    QMap<QString, QString> owner;
    for (QAction* a : w->findChildren<QAction*>()) {
        for (const QKeySequence& k : a->shortcuts()) {
            const QString key = k.toString(QKeySequence::PortableText);
            const QString name = a->objectName().isEmpty() ? a->text() : a->objectName();
            QVERIFY2(!owner.contains(key),
                     qPrintable(key + " is bound to both " + owner.value(key) + " and " + name));
            owner.insert(key, name);
        }
    }
    // The standard views' keys are in the View menu (a newcomer found them
    // only in the README).
    QCOMPARE(owner.value("0"), QString("action.view.iso"));
    QCOMPARE(owner.value("1"), QString("action.view.front"));
    QCOMPARE(owner.value("3"), QString("action.view.right"));
    QCOMPARE(owner.value("7"), QString("action.view.top"));
    QVERIFY(owner.contains("Ctrl+Z") && owner.contains("Ctrl+Shift+Z") && owner.contains("Ctrl+Y"));

    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    w->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(w.get()));
    w->featureTree()->setFocus();
    QWidget* focus = QApplication::focusWidget();
    QVERIFY(focus);
    QTest::keyClick(focus, Qt::Key_Z, Qt::ControlModifier);
    QVERIFY(w->session()->document().root.children.empty());
    QTest::keyClick(focus, Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
    QCOMPARE(w->session()->document().root.children.size(), std::size_t(1));
    QTest::keyClick(focus, Qt::Key_Z, Qt::ControlModifier);
    QVERIFY(w->session()->document().root.children.empty());
    QTest::keyClick(focus, Qt::Key_Y, Qt::ControlModifier);
    QCOMPARE(w->session()->document().root.children.size(), std::size_t(1));
}

void MainWindowTest::theWheelEditsOnlyTheFieldBeingEdited()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    w->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(w.get()));
    w->featureTree()->setFocus();
    QuantityEdit* x = field(*w, "size.x");
    QVERIFY(x && !x->hasFocus());
    const std::string before = w->session()->document().serialize();
    const int steps = w->session()->undoStack()->count();
    const auto wheel = [&](QWidget* target) {
        const QPointF at(target->width() / 2.0, target->height() / 2.0);
        QWheelEvent e(at, target->mapToGlobal(at), QPoint(), QPoint(0, 120), Qt::NoButton, Qt::NoModifier,
                      Qt::NoScrollPhase, false);
        QApplication::sendEvent(target, &e);
    };
    // The wheel passing over a field on its way down the panel: nothing changes.
    wheel(x);
    QCOMPARE(QString::fromStdString(w->session()->document().serialize()), QString::fromStdString(before));
    QCOMPARE(w->session()->undoStack()->count(), steps);
    // Clicked into, the field takes the wheel.
    QTest::mouseClick(x->findChild<QLineEdit*>(), Qt::LeftButton);
    QTRY_VERIFY(x->hasFocus());
    wheel(x);
    QTRY_COMPARE(w->session()->undoStack()->count(), steps + 1);
}

void MainWindowTest::ctrlZRightAfterTypingAValueUndoesIt()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    w->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(w.get()));
    QuantityEdit* x = field(*w, "size.x");
    const double old = x->value();
    typeInto(x, "600");
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, 600.0);
    QVERIFY(x->hasFocus()); // Enter keeps the focus in the field
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_Z, Qt::ControlModifier);
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, old);
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, 600.0);

    // Typing not yet committed: Ctrl+Z undoes the typing, as in any text field.
    x = field(*w, "size.x");
    x->setFocus();
    x->selectAll();
    QTest::keyClicks(x, "7");
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_Z, Qt::ControlModifier);
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, 600.0);
    QVERIFY(x->text().startsWith("600"));

    // The name field, and a click on the selected row of the tree (which
    // used to open a rename editor that swallowed the key).
    auto* name = w->propertyEditor()->findChild<QLineEdit*>("field.name");
    QVERIFY(name);
    name->setFocus();
    QTest::keyClicks(name, "Side");
    QTest::keyClick(name, Qt::Key_Return);
    QCOMPARE(w->session()->document().root.find("box")->name.value_or(""), std::string("Side"));
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_Z, Qt::ControlModifier);
    QVERIFY(!w->session()->document().root.find("box")->name.has_value());
    clickRow(*w, "box");
    QTest::qWait(QApplication::doubleClickInterval() + 100); // no rename editor opens
    for (const QLineEdit* e : w->featureTree()->findChildren<QLineEdit*>())
        QVERIFY2(!e->isVisible(), "a click on the selected row opened a rename editor");
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_Z, Qt::ControlModifier);
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, old);
}

void MainWindowTest::theToolbarKeepsItsButtonsWhereTheyAre()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    auto* bar = w->findChild<QToolBar*>("toolbar.file");
    QVERIFY(bar);
    QWidget* undo = bar->widgetForAction(action(w.get(), "action.undo"));
    QWidget* exportButton = bar->widgetForAction(action(w.get(), "action.export"));
    QVERIFY(undo && exportButton);
    const QRect undoBefore = undo->geometry(), exportBefore = exportButton->geometry();
    // An edit with a long command name.
    action(w.get(), "action.add.cylinder")->trigger();
    typeInto(field(*w, "radius"), "12");
    QVERIFY(action(w.get(), "action.undo")->text().size() > 8); // the menu names the command
    QCOMPARE(static_cast<QToolButton*>(undo)->text(), QString("Undo"));
    QCOMPARE(undo->geometry(), undoBefore);
    QCOMPARE(exportButton->geometry(), exportBefore);
}

void MainWindowTest::aBundledExampleOpensAsAnUntitledCopy()
{
    // An installed examples folder with the stool in it.
    QTemporaryDir installed;
    const std::filesystem::path example = std::filesystem::path(installed.path().toStdString()) / "stool.kerf";
    std::filesystem::copy_file(std::filesystem::path(KERF_EXAMPLES_DIR) / "stool.kerf", example);
    const std::string original = Document::load(example).serialize();
    MainWindowOptions options;
    options.examplesFolder = installed.path().toStdString();
    QString suggested;
    options.askFile = [&](bool, const QString& s) {
        suggested = s;
        return QString(); // cancelled
    };
    int askedToSave = 0;
    options.askSave = [&](const QString&) {
        ++askedToSave;
        return QMessageBox::Save; // Enter on the prompt
    };
    auto w = makeWindow(recovery_.path(), options);
    QVERIFY(w->openFile(example));
    QVERIFY(!w->session()->path().has_value());
    w->selectNodes({w->session()->document().root.children.front().id});
    action(w.get(), "action.duplicate")->trigger();
    QVERIFY(w->session()->isModified());
    // Save, and the prompt's default answer, ask where: the installed file stays as it was.
    action(w.get(), "action.save")->trigger();
    QVERIFY2(suggested.endsWith("/stool.kerf"), qPrintable(suggested));
    QVERIFY(suggested != QString::fromStdString(example.string()));
    QVERIFY(!w->openFile(example)); // the prompt: Save, then the cancelled file dialog
    QCOMPARE(askedToSave, 1);
    QCOMPARE(QString::fromStdString(Document::load(example).serialize()), QString::fromStdString(original));
    // Outside the examples folder a file opens as itself.
    const std::filesystem::path mine = std::filesystem::path(files_.path().toStdString()) / "my-stool.kerf";
    std::filesystem::copy_file(example, mine, std::filesystem::copy_options::overwrite_existing);
    options.askSave = [](const QString&) { return QMessageBox::Discard; };
    auto other = makeWindow(recovery_.path(), options);
    QVERIFY(other->openFile(mine));
    QCOMPARE(other->session()->path(), std::optional<std::filesystem::path>(mine));
    // Open starts in the open document's folder; with none, in the last
    // file's (it started wherever Kerf was started from: /root for a newcomer).
    const QString folder = QFileInfo(files_.path()).absoluteFilePath();
    action(other.get(), "action.open")->trigger();
    QCOMPARE(suggested, folder);
    action(other.get(), "action.new")->trigger();
    action(other.get(), "action.open")->trigger();
    QCOMPARE(suggested, folder);
}

void MainWindowTest::undoStepsAndMessagesSpeakThePanelsLanguage()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.cone")->trigger();
    typeInto(field(*w, "radius_bottom"), "30");
    QUndoStack* stack = w->session()->undoStack();
    QCOMPARE(stack->undoText(), QString("Set bottom radius of the cone"));
    typeInto(field(*w, "translate.x"), "5");
    QCOMPARE(stack->undoText(), QString("Set position X of the cone"));
    auto* name = w->propertyEditor()->findChild<QLineEdit*>("field.name");
    name->setFocus();
    QTest::keyClicks(name, "Foot");
    QTest::keyClick(name, Qt::Key_Return);
    typeInto(field(*w, "height"), "40");
    QCOMPARE(stack->undoText(), QString("Set height of Foot"));
    action(w.get(), "action.add.cylinder")->trigger();
    w->selectNodes({"cylinder"});
    action(w.get(), "action.delete")->trigger();
    QCOMPARE(stack->undoText(), QString("Delete the cylinder"));
    for (QAction* a : w->findChildren<QAction*>())
        QVERIFY2(!a->text().contains("radius_") && !a->text().contains("cylinder-"), qPrintable(a->text()));
}

void MainWindowTest::unreadableTextIsSaidUnderItsFieldAndOlderMessagesGo()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    w->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(w.get())); // focus moves only in the active window
    const Document before = w->session()->document();
    PropertyEditor* p = w->propertyEditor();
    // Enter on text that is no number: said under the field, nothing changes.
    typeInto(field(*w, "size.x"), "twelve");
    QVERIFY2(p->errorFor("size.x").contains("cannot read 'twelve'"), qPrintable(p->errorFor("size.x")));
    QVERIFY(w->session()->document() == before);
    // A refusal in another field replaces it.
    typeInto(field(*w, "size.y"), "-3");
    QVERIFY(!p->errorFor("size.y").isEmpty());
    QCOMPARE(p->errorFor("size.x"), QString());
    // Leaving a field with unreadable text says so too.
    QuantityEdit* z = field(*w, "size.z");
    z->setFocus();
    z->selectAll();
    QTest::keyClicks(z, "1 furlong");
    field(*w, "size.x")->setFocus();
    QTRY_VERIFY2(p->errorFor("size.z").contains("furlong"), qPrintable(p->errorFor("size.z")));
    QCOMPARE(p->errorFor("size.y"), QString());
    // An edit that goes through clears what is left.
    typeInto(field(*w, "size.x"), "40");
    for (const QString key : {"size.x", "size.y", "size.z"})
        QCOMPARE(p->errorFor(key), QString());
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, 40.0);
}

void MainWindowTest::aStatusMessageGetsTheWholeBar()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf"));
    QVERIFY(waitForViewport(*w));
    QStatusBar* bar = w->statusBar();
    auto* voxels = bar->findChild<QLabel*>("status.voxels");
    bar->clearMessage(); // "Opened ..."
    QVERIFY(voxels && voxels->isVisible()); // the figures, while there is no message
    // A refused delete: the status bar is the only word on it.
    w->selectNodes({w->session()->document().root.id});
    action(w.get(), "action.delete")->trigger();
    const QString message = bar->currentMessage();
    QVERIFY2(message.startsWith("Cannot delete: "), qPrintable(message));
    int room = bar->width();
    for (const QLabel* l : bar->findChildren<QLabel*>())
        if (l->objectName().startsWith("status.") && l->isVisible()) room -= l->width();
    QVERIFY2(room > bar->fontMetrics().horizontalAdvance(message) + 8,
             qPrintable(QString("%1 px for a %2 px message").arg(room).arg(bar->fontMetrics().horizontalAdvance(message))));
    bar->clearMessage();
    QVERIFY(voxels->isVisible());
}

void MainWindowTest::theSectionKeepsATypedOffsetAndTheSliderFollowsIt()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf"));
    QVERIFY(waitForVoxels(*w));
    auto* on = w->findChild<QCheckBox*>("section.enabled");
    auto* slider = w->findChild<QSlider*>("section.slider");
    auto* offset = w->findChild<QuantityEdit*>("section.offset");
    QVERIFY(on && slider && offset);
    on->setChecked(true);
    const int middle = slider->value();
    typeInto(offset, "123.4");
    QCOMPARE(w->viewport()->section().offset, 123.4);
    QCOMPARE(offset->value(), 123.4); // not the slider's rounding of it
    QVERIFY(slider->value() != middle); // the slider went there too
    const int at = slider->value();
    on->setChecked(false);
    on->setChecked(true);
    QCOMPARE(offset->value(), 123.4);
    QCOMPARE(slider->value(), at);
    QCOMPARE(w->viewport()->section().offset, 123.4);
    // The slider moved by hand sets the offset.
    slider->setValue(at + 100);
    QVERIFY(offset->value() > 123.4);
    QCOMPARE(w->viewport()->section().offset, offset->value());
}

void MainWindowTest::theViewsFeatureSizeIsSetWithNothingSelected()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "stool.kerf"));
    QVERIFY(waitForVoxels(*w));
    w->selectNodes({});
    // (The panel is rebuilt after each edit: the field is looked up each time.)
    const auto fs = [&] { return w->propertyEditor()->findChild<QuantityEdit*>("part.featureSize"); };
    QVERIFY(fs());
    QCOMPARE(fs()->value(), *w->session()->document().settings.featureSize);
    typeInto(fs(), "2");
    QCOMPARE(*w->session()->document().settings.featureSize, 2.0);
    QCOMPARE(w->session()->undoStack()->undoText(), QString("Set the view's feature size"));
    QVERIFY(waitForVoxels(*w));
    QCOMPARE(w->voxelizer()->latest()->layout.voxelSize, 2.0);
    // Refused like any other bad value, beside the field.
    typeInto(fs(), "0");
    QCOMPARE(*w->session()->document().settings.featureSize, 2.0);
    QVERIFY2(w->propertyEditor()->errorFor("part.featureSize").contains("feature_size"),
             qPrintable(w->propertyEditor()->errorFor("part.featureSize")));
    QCOMPARE(fs()->value(), 2.0);
    action(w.get(), "action.undo")->trigger();
    QCOMPARE(*w->session()->document().settings.featureSize, 0.5);
    QTRY_COMPARE(fs()->value(), 0.5);

    // A length with zeros too many (issue 17 item 9: once accepted without a
    // word, the view's voxels then a kilometre): refused beside the field.
    action(w.get(), "action.add.box")->trigger();
    const Document before = w->session()->document();
    typeInto(field(*w, "size.x"), "1e9");
    QVERIFY2(w->propertyEditor()->errorFor("size.x").contains("limited to 100000000 mm (100 km)"),
             qPrintable(w->propertyEditor()->errorFor("size.x")));
    QVERIFY(w->session()->document() == before);
    // Far past it, the number typed is the number quoted (it was 1e9, the
    // field's own limit, whatever was typed).
    typeInto(field(*w, "size.x"), "1e30");
    QVERIFY2(w->propertyEditor()->errorFor("size.x").contains("1e+30 mm"),
             qPrintable(w->propertyEditor()->errorFor("size.x")));
    QVERIFY(w->session()->document() == before);
    // A position's refusal names the field as its row does (it said "Box: is
    // 1e+30 mm", the reader's "transform.translate[2]" unknown to the labels).
    typeInto(field(*w, "translate.z"), "1e30");
    QVERIFY2(w->propertyEditor()->errorFor("translate.z").startsWith("Position Z of "),
             qPrintable(w->propertyEditor()->errorFor("translate.z")));
    QVERIFY(w->session()->document() == before);
}

void MainWindowTest::theLayoutIsRememberedAndTheViewFollowsThePartsScale()
{
    QSettings().clear();
    auto w = makeWindow(recovery_.path(), {}, true);
    // The Properties panel starts taller than the section's four controls.
    auto* props = w->findChild<QDockWidget*>("dock.properties");
    auto* section = w->findChild<QDockWidget*>("dock.section");
    QTRY_VERIFY2(props->height() > 2 * section->height(),
                 qPrintable(QString("%1 against %2").arg(props->height()).arg(section->height())));
    // A dock closed and the window closed: the next session has it closed.
    section->close();
    w->close();
    w.reset();
    auto again = makeWindow(recovery_.path(), {}, true);
    QVERIFY(!again->findChild<QDockWidget*>("dock.section")->isVisible());
    QVERIFY(again->findChild<QDockWidget*>("dock.properties")->isVisible());
    again.reset();
    QSettings().clear();

    // A board grown from 20 mm to 1800 mm is framed again; a small change is not.
    auto v = makeWindow(recovery_.path());
    action(v.get(), "action.new")->trigger();
    action(v.get(), "action.add.box")->trigger();
    for (const char* axis : {"size.x", "size.y", "size.z"})
        typeInto(field(*v, axis), "20");
    QVERIFY(waitForViewport(*v));
    const double small = v->viewport()->view().distance();
    typeInto(field(*v, "size.x"), "25");
    QVERIFY(waitForViewport(*v));
    QCOMPARE(v->viewport()->view().distance(), small);
    typeInto(field(*v, "size.x"), "1800");
    QVERIFY(waitForViewport(*v));
    QVERIFY2(v->viewport()->view().distance() > 20.0 * small,
             qPrintable(QString("%1 against %2").arg(v->viewport()->view().distance()).arg(small)));
    // Undone to nothing and redone: framed on the 1800 mm board again (a
    // newcomer's redone table stayed framed on the 20 mm box that its undo
    // passed through on the way to nothing).
    const double large = v->viewport()->view().distance();
    QUndoStack* steps = v->session()->undoStack();
    while (steps->canUndo()) {
        steps->undo();
        QVERIFY(waitForViewport(*v));
    }
    QVERIFY(v->session()->document().root.children.empty());
    while (steps->canRedo()) {
        steps->redo();
        QVERIFY(waitForViewport(*v));
    }
    QCOMPARE(v->viewport()->view().distance(), large);

    // A restored autosave of another part is framed.
    QTemporaryDir folder;
    {
        auto crashed = makeWindow(folder.path());
        action(crashed.get(), "action.new")->trigger();
        action(crashed.get(), "action.add.sphere")->trigger();
        typeInto(field(*crashed, "translate.x"), "3000");
        crashed->autosaveNow();
        crashed->recovery().abandon();
    }
    MainWindowOptions restoring;
    restoring.askRestore = [](const RecoveryCandidate&) { return true; };
    auto r = makeWindow(folder.path(), restoring);
    QVERIFY(r->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "stool.kerf"));
    QVERIFY(waitForViewport(*r));
    r->offerRecovery();
    QVERIFY(waitForViewport(*r));
    QTRY_VERIFY2(glm::length(r->viewport()->view().target() - glm::dvec3(3000, 0, 0)) < 50.0,
                 qPrintable(QString::number(r->viewport()->view().target().x)));
}

void MainWindowTest::anOperationFromTheToolbarActsOnTheSelectedFeature()
{
    auto w = makeWindow(recovery_.path());
    auto* bar = w->findChild<QToolBar*>("toolbar.features");
    QVERIFY(bar);
    const auto click = [&](const char* name) {
        QWidget* button = bar->widgetForAction(action(w.get(), name));
        QVERIFY2(button && button->isVisible(), name);
        QTest::mouseClick(button, Qt::LeftButton);
    };
    action(w.get(), "action.new")->trigger();
    click("action.add.cylinder");
    typeInto(field(*w, "radius"), "15");
    clickRow(*w, "cylinder");
    // Select the leg, press Array: an array of that leg.
    click("action.add.array");
    const Node* array = w->session()->document().root.find("array");
    QVERIFY(array);
    QCOMPARE(array->children.size(), std::size_t(1));
    QCOMPARE(array->children.front().id, std::string("cylinder"));
    QCOMPARE(w->selectedNodeIds(), std::vector<std::string>{"array"});
    // A count is whole: 2.5 is refused beside the field in the panel's
    // words, not rounded to 3 without a word (a newcomer's Count Z).
    const auto counts = [&] { return w->session()->document().root.find("array")->as<ArrayParams>().count; };
    const auto before = counts();
    typeInto(field(*w, "count.z"), "2.5");
    QCOMPARE(counts(), before);
    QCOMPARE(w->propertyEditor()->errorFor("count.z"), QString("Count Z of the array: must be a whole number, not 2.5"));
    typeInto(field(*w, "count.z"), "3");
    QCOMPARE(counts()[2], std::int64_t(3));
    QCOMPARE(w->propertyEditor()->errorFor("count.z"), QString());
    // Nothing selected: a mirror with a placeholder box, which the next
    // primitive pressed replaces.
    w->selectNodes({});
    click("action.add.mirror");
    QCOMPARE(w->session()->document().root.find("mirror")->children.front().id, std::string("mirror-box"));
    click("action.add.sphere");
    const Node* mirror = w->session()->document().root.find("mirror");
    QCOMPARE(mirror->children.size(), std::size_t(1));
    QCOMPARE(mirror->children.front().type, NodeType::Sphere);
    QVERIFY(!w->session()->document().root.find("mirror-box"));
    // One undo step each.
    action(w.get(), "action.undo")->trigger();
    QVERIFY(w->session()->document().root.find("mirror-box"));
}

void MainWindowTest::theTreeMarksTheBaseAndAsksBeforeAToolGoesAboveIt()
{
    const QString doc = files_.path() + "/board.kerf";
    {
        QFile f(doc);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union","children":[
            {"id":"d","type":"difference","children":[
                {"id":"board","type":"box","size":[100,50,18]},
                {"id":"hole","type":"cylinder","radius":4,"height":30}]}]}})");
    }
    QStringList asked;
    bool answer = false;
    MainWindowOptions options;
    options.askConfirm = [&](const QString& q) {
        asked << q;
        return answer;
    };
    auto w = makeWindow(recovery_.path(), options);
    QVERIFY(w->openFile(doc.toStdString()));
    FeatureTreeModel* m = w->featureModel();
    const auto typeText = [&](const char* id) {
        return m->data(m->indexOf(id).siblingAtColumn(FeatureTreeModel::TypeColumn), Qt::DisplayRole).toString();
    };
    QCOMPARE(typeText("board"), QString("Box · base"));
    QCOMPARE(typeText("hole"), QString("Cylinder · cut"));
    QCOMPARE(typeText("d"), QString("Difference"));
    // Moved off the board, the hole cuts nothing, and the tree says so
    // (a newcomer's dowel hole went missing from the part and its file
    // without a word); back on it, it cuts again.
    QVERIFY(w->session()->apply("Off", [](Document& d) { d.root.find("hole")->transform.translate.y = 100; }));
    QCOMPARE(typeText("hole"), QString("Cylinder · cuts nothing"));
    const QModelIndex holeType = m->indexOf("hole").siblingAtColumn(FeatureTreeModel::TypeColumn);
    QVERIFY2(m->data(holeType, Qt::ToolTipRole).toString().contains("cuts nothing from it"),
             qPrintable(m->data(holeType, Qt::ToolTipRole).toString()));
    action(w.get(), "action.undo")->trigger();
    QCOMPARE(typeText("hole"), QString("Cylinder · cut"));

    // Drag the hole above the board: asked first; "no" changes nothing.
    const Document before = w->session()->document();
    QMimeData* data = m->mimeData({m->indexOf("hole")});
    m->dropMimeData(data, Qt::MoveAction, 0, 0, m->indexOf("d"));
    QCOMPARE(asked.size(), 1);
    QVERIFY2(asked.front().contains("would cut from the cylinder instead"), qPrintable(asked.front()));
    QVERIFY(w->session()->document() == before);
    // "Yes" moves it, one undo step.
    answer = true;
    m->dropMimeData(data, Qt::MoveAction, 0, 0, m->indexOf("d"));
    delete data;
    QCOMPARE(w->session()->document().root.find("d")->children.front().id, std::string("hole"));
    QCOMPARE(w->session()->undoStack()->undoText(), QString("Move the cylinder"));
    action(w.get(), "action.undo")->trigger();
    QVERIFY(w->session()->document() == before);
}

void MainWindowTest::deletingWhatADifferenceCutsFromAsksFirst()
{
    // A newcomer deleted the board of a shelf side and got its pin holes
    // back as solid pegs, without a word.
    const QString doc = files_.path() + "/side.kerf";
    {
        QFile f(doc);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union","children":[
            {"id":"leg","type":"box","size":[40,40,400]},
            {"id":"d","type":"difference","name":"Shelf side","children":[
                {"id":"board","type":"box","name":"Board","size":[100,50,18]},
                {"id":"hole","type":"cylinder","name":"Pin hole","radius":2.5,"height":30},
                {"id":"hole2","type":"cylinder","radius":2.5,"height":30,"translate":[20,0,0]}]}]}})");
    }
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(doc.toStdString()));
    const Document before = w->session()->document();
    const auto deleteAnswering = [&](const std::vector<std::string>& ids, const char* button) {
        w->selectNodes(ids);
        MessageBoxAnswerer answer(button);
        action(w.get(), "action.delete")->trigger();
        return std::pair(answer.answered(), answer.text());
    };

    // Cancel, the default: nothing changes.
    auto [asked, text] = deleteAnswering({"board"}, "delete.base.cancel");
    QVERIFY(asked);
    QVERIFY2(text.contains("Board is what Shelf side cuts from.") &&
                 text.contains("Shelf side would cut from Pin hole instead: what it cuts away would become solid."),
             qPrintable(text));
    QVERIFY(w->session()->document() == before);

    // The whole difference: one undo step.
    std::tie(asked, text) = deleteAnswering({"board"}, "delete.base.whole");
    QVERIFY(asked);
    QVERIFY(!w->session()->document().root.find("d"));
    QVERIFY(w->session()->document().root.find("leg"));
    QCOMPARE(w->session()->undoStack()->undoText(), QString("Delete Shelf side")); // what goes, not what was selected
    action(w.get(), "action.undo")->trigger();
    QVERIFY(w->session()->document() == before);

    // Only the selection, as asked: the first tool becomes the body.
    std::tie(asked, text) = deleteAnswering({"board"}, "delete.base.only");
    QVERIFY(asked);
    QCOMPARE(w->session()->document().root.find("d")->children.front().id, std::string("hole"));
    action(w.get(), "action.undo")->trigger();
    QVERIFY(w->session()->document() == before);

    // The board with every tool: the difference is left with nothing and
    // goes too, without a question (there is no other way on), and says so.
    std::tie(asked, text) = deleteAnswering({"board", "hole", "hole2"}, "delete.base.cancel");
    QVERIFY2(!asked, qPrintable(text));
    QVERIFY(!w->session()->document().root.find("d"));
    QCOMPARE(w->session()->undoStack()->undoText(), QString("Delete 3 features and Shelf side, left empty"));
    action(w.get(), "action.undo")->trigger();
    QVERIFY(w->session()->document() == before);

    // A tool goes without a question.
    std::tie(asked, text) = deleteAnswering({"hole"}, "delete.base.cancel");
    QVERIFY2(!asked, qPrintable(text));
    QVERIFY(!w->session()->document().root.find("hole"));
    QCOMPARE(w->session()->document().root.find("d")->children.front().id, std::string("board"));
    action(w.get(), "action.undo")->trigger();

    // The board that other features' expressions refer to: refused before
    // any question, naming every use (a newcomer was asked about the
    // difference first, then refused, one use named).
    QVERIFY(w->session()->apply("Refer", [](Document& d) {
        d.root.find("hole")->expressions["height"] = "board.size[2] + 12";
        d.root.find("leg")->expressions["size[0]"] = "board.size[0] - 60";
    }));
    const Document referred = w->session()->document();
    std::tie(asked, text) = deleteAnswering({"board"}, "delete.base.whole");
    QVERIFY2(!asked, qPrintable(text));
    QVERIFY(w->session()->document() == referred);
    QVERIFY2(w->lastMessage() == "Cannot delete: Board is used by Size X of the box, Height of Pin hole: change those "
                                 "first.",
             qPrintable(w->lastMessage()));
}

void MainWindowTest::exportDialogWritesAClosedMesh()
{
    auto w = makeWindow(recovery_.path());
    ExportDialog* dialog = openExportDialog(*w, "stool.kerf");
    QVERIFY(dialog);
    auto* dismiss = dialog->findChild<QPushButton*>("export.dismiss");
    QVERIFY(dismiss);
    QCOMPARE(dismiss->text(), QString("Cancel"));
    // Someone who changes nothing gets the mesh simplified to the default
    // tolerance; unticked, every cell's triangles (measured against below).
    QVERIFY(dialog->findChild<QCheckBox*>("export.simplify")->isChecked());
    QVERIFY(dialog->findChild<QuantityEdit*>("export.tolerance")->isEnabled());
    QCOMPARE(dialog->findChild<QuantityEdit*>("export.tolerance")->value(), kDefaultExportTolerance);
    dialog->findChild<QCheckBox*>("export.simplify")->setChecked(false);
    QVERIFY(!dialog->findChild<QuantityEdit*>("export.tolerance")->isEnabled());
    const QString out = files_.path() + "/stool.stl";
    dialog->findChild<QLineEdit*>("export.path")->setText(out);
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(4.0);
    QSignalSpy done(dialog, &ExportDialog::finished);
    QTest::mouseClick(dialog->findChild<QPushButton*>("export.start"), Qt::LeftButton);
    QVERIFY(done.wait(120000));
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));
    QVERIFY(dialog->outcome().closed);
    QCOMPARE(dismiss->text(), QString("Close")); // the file is written: nothing to cancel

    // The file itself, read back as a slicer reads it (welded by its float32
    // coordinates): every edge between two faces, the triangles reported.
    {
        const MeshReport report = checkMesh(test::readMeshFile(out.toStdString()));
        QCOMPARE(report.triangles, dialog->outcome().triangles);
        QVERIFY(report.watertight());
        QVERIFY(report.volume > 0.0);
        QVERIFY2(dialog->outcome().message.contains("As read back: closed"), qPrintable(dialog->outcome().message));
    }

    // 3MF chosen in the format box: the extension follows, and a tolerance
    // gives far fewer triangles than the marching-cubes mesh, within it.
    auto* format = dialog->findChild<QComboBox*>("export.format");
    format->setCurrentIndex(2);
    QCOMPARE(dialog->findChild<QLineEdit*>("export.path")->text(), files_.path() + "/stool.3mf");
    dialog->findChild<QCheckBox*>("export.simplify")->setChecked(true);
    dialog->findChild<QuantityEdit*>("export.tolerance")->setValue(0.5);
    const std::size_t plainTriangles = dialog->outcome().triangles;
    QTest::mouseClick(dialog->findChild<QPushButton*>("export.start"), Qt::LeftButton);
    QVERIFY(done.wait(600000));
    QVERIFY2(dialog->outcome().written, qPrintable(dialog->outcome().message));
    {
        const MeshReport report = checkMesh(test::readMeshFile((files_.path() + "/stool.3mf").toStdString()));
        QVERIFY(report.watertight());
        QCOMPARE(report.triangles, dialog->outcome().triangles);
        if (dialog->outcome().simplified) {
            QVERIFY2(report.triangles * 3 < plainTriangles, qPrintable(dialog->outcome().message));
            // At 4 mm cells the middle of the stool's seat, where its blends
            // meet, keeps triangles over 0.5 mm that no split mends; the
            // dialog says which and how far (the tolerance held by the
            // distance, not |f|: mesher/src/SampleDistance.hpp).
            const QString message = dialog->outcome().message;
            QVERIFY2(message.contains("within 0.5 mm") || message.contains("beyond the tolerance of 0.5 mm"),
                     qPrintable(message));
            // And the other way: the part's points against the file.
            QVERIFY2(message.contains(QRegularExpression("points of the part's surface that the cells found lie "
                                                         "(within|beyond)")),
                     qPrintable(message));
        }
    }
    // A name the dialog cannot tell the format of is refused, nothing written.
    dialog->findChild<QLineEdit*>("export.path")->setText(files_.path() + "/stool.obj");
    dialog->start();
    QVERIFY(!dialog->outcome().written);
    QCOMPARE(dialog->findChild<QProgressBar*>("export.progress")->value(), 0); // not the 3MF's 100 %
    QVERIFY2(dialog->outcome().message.contains(".stl (STL) or .3mf (3MF)"), qPrintable(dialog->outcome().message));
    QVERIFY(!QFile::exists(files_.path() + "/stool.obj"));
    dialog->findChild<QCheckBox*>("export.simplify")->setChecked(false);
    dialog->findChild<QLineEdit*>("export.path")->setText(files_.path() + "/stool.3mf");
    format->setCurrentIndex(0);
    QCOMPARE(dialog->findChild<QLineEdit*>("export.path")->text(), files_.path() + "/stool.stl");

    // Cancelled: nothing is written.
    const QString cancelled = files_.path() + "/cancelled.stl";
    dialog->findChild<QLineEdit*>("export.path")->setText(cancelled);
    // (A size the machine's budget allows even under a sanitizer on a busy
    // machine: the export estimates before it meshes, so the cancel always
    // arrives before the meshing starts.)
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(1.0);
    dialog->start();
    dialog->cancel();
    QVERIFY(done.wait(120000));
    QVERIFY2(dialog->outcome().cancelled, qPrintable(dialog->outcome().message));
    QVERIFY(!QFile::exists(cancelled));
    QCOMPARE(dialog->findChild<QProgressBar*>("export.progress")->value(), 0); // nothing written: no bar part way

    // Refused before any meshing (issue 14): a feature size no machine could
    // mesh, with the size that would fit; a folder as the output, unchanged.
    const QString tooFine = files_.path() + "/too-fine.stl";
    dialog->findChild<QLineEdit*>("export.path")->setText(tooFine);
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(0.00001);
    QElapsedTimer clock;
    clock.start();
    dialog->start();
    QVERIFY(done.wait(60000));
    QVERIFY(clock.elapsed() < 20000);
    QVERIFY(!dialog->outcome().written);
    QVERIFY2(dialog->outcome().message.contains("Not exported: meshing at 1e-05 mm needs about") &&
                 dialog->outcome().message.contains("mm or more"),
             qPrintable(dialog->outcome().message));
    QVERIFY(!QFile::exists(tooFine));
    // A tolerance finer than STL's float32 coordinates can hold: refused at
    // once, with the finest it holds (it ran for minutes and came back with
    // every triangle "over" it).
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(4.0);
    dialog->findChild<QCheckBox*>("export.simplify")->setChecked(true);
    dialog->findChild<QuantityEdit*>("export.tolerance")->setValue(0.000001);
    clock.restart();
    dialog->start();
    QVERIFY(done.wait(60000));
    QVERIFY(clock.elapsed() < 20000);
    QVERIFY(!dialog->outcome().written);
    QVERIFY2(dialog->outcome().message.contains("Not exported: A tolerance of 1e-06 mm is finer than a binary STL "
                                                "file can hold") &&
                 dialog->outcome().message.contains("the finest tolerance it holds is"),
             qPrintable(dialog->outcome().message));
    QVERIFY(!QFile::exists(tooFine));
    dialog->findChild<QCheckBox*>("export.simplify")->setChecked(false);
    QDir(files_.path()).mkdir("a-folder.stl");
    dialog->findChild<QLineEdit*>("export.path")->setText(files_.path() + "/a-folder.stl");
    dialog->findChild<QuantityEdit*>("export.featureSize")->setValue(4.0);
    dialog->start();
    QVERIFY(done.wait(60000));
    QVERIFY(!dialog->outcome().written);
    QVERIFY2(dialog->outcome().message.contains("is a folder, not a regular file"), qPrintable(dialog->outcome().message));
    QVERIFY(QFileInfo(files_.path() + "/a-folder.stl").isDir());
}

void MainWindowTest::cutListMeasureAndSection()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side.kerf"));
    action(w.get(), "action.cutList")->trigger();
    auto* cut = w->findChild<CutListDialog*>("cutListDialog");
    QVERIFY(cut);
    QTRY_VERIFY_WITH_TIMEOUT(cut->ready(), 30000);
    QCOMPARE(cut->rows().size(), std::size_t(1));
    QCOMPARE(cut->rows()[0].length, 1800.0);
    const auto* counted = cut->findChild<QLabel*>("cutlist.status");
    QVERIFY(counted);
    QVERIFY2(counted->text().startsWith("1 row, 1 piece; dimensions within"), qPrintable(counted->text()));
    const QString csv = files_.path() + "/cut.csv";
    QVERIFY(cut->exportCsv(csv));
    QFile f(csv);
    QVERIFY(f.open(QIODevice::ReadOnly));
    QVERIFY(f.readAll().contains("1800.00,300.00,18.00"));

    action(w.get(), "action.boundingBox")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(w->measureText().contains("Bounding box: 18.00 x 300.00 x 1800.00 mm"), 30000);

    // Measure: two clicks on the part give their distance.
    QVERIFY(waitForViewport(*w));
    action(w.get(), "action.view.right")->trigger(); // the panel's 300 x 1800 face
    action(w.get(), "action.measure")->trigger();
    qt::ViewportWidget* v = w->viewport();
    const QPoint a(v->width() / 2, v->height() / 3), b(v->width() / 2, 2 * v->height() / 3);
    const qt::ViewportPick pa = v->pickAt(a), pb = v->pickAt(b);
    QVERIFY(pa.hit && pb.hit);
    emit v->clicked(pa);
    emit v->clicked(pb);
    const QString expected = QString::number(glm::length(pb.point - pa.point), 'f', 2);
    QVERIFY2(w->measureText().contains("Distance: " + expected + " mm"), qPrintable(w->measureText()));

    // Section: across Y through the middle; the viewport traces with it.
    // It keeps the half away from the eye (the front view looks from -Y),
    // so the cut faces the viewer: the plane's normal, pointing at the half
    // cut away, is -Y, and "Keep the other side" says so (a newcomer looking
    // from the front saw the uncut face). The person may change it.
    action(w.get(), "action.view.front")->trigger();
    w->findChild<QCheckBox*>("section.enabled")->setChecked(true);
    w->findChild<QComboBox*>("section.axis")->setCurrentIndex(1);
    QVERIFY(v->section().enabled);
    QCOMPARE(v->section().normal, glm::dvec3(0, -1, 0));
    auto* flip = w->findChild<QCheckBox*>("section.flip");
    QVERIFY(flip->isChecked());
    flip->setChecked(false);
    QCOMPARE(v->section().normal, glm::dvec3(0, 1, 0));
    // From the back (eye at +Y), turned on again: the other half, facing it.
    action(w.get(), "action.view.back")->trigger();
    w->findChild<QCheckBox*>("section.enabled")->setChecked(false);
    w->findChild<QCheckBox*>("section.enabled")->setChecked(true);
    QCOMPARE(v->section().normal, glm::dvec3(0, 1, 0));
    QVERIFY(!flip->isChecked());
    const QImage cutPicture = v->grabFrame();
    QVERIFY(!cutPicture.isNull());
}

void MainWindowTest::refusedFilesChangeNothing()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "stool.kerf"));
    const Document before = w->session()->document();
    const QString broken = files_.path() + "/broken.kerf";
    QFile f(broken);
    QVERIFY(f.open(QIODevice::WriteOnly));
    f.write(R"({"format":"kerf","version":1,"root":{"id":"s","type":"sphere","radius":-1}})");
    f.close();
    QVERIFY(!w->openFile(broken.toStdString()));
    QVERIFY(w->session()->document() == before);
    QVERIFY2(w->lastMessage().contains("broken.kerf") && w->lastMessage().contains("radius"),
             qPrintable(w->lastMessage()));
    // Saving into a folder that does not exist: refused, the document keeps its file.
    QVERIFY(!w->saveAs(std::filesystem::path((files_.path() + "/no/such/folder/x.kerf").toStdString())));
    QCOMPARE(w->session()->path().value().filename().string(), std::string("stool.kerf"));
}

void MainWindowTest::dragAndDropRegroupsInTheTree()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    w->selectNodes({}); // (with the box selected, the union would take it)
    action(w.get(), "action.add.union")->trigger(); // a union with a box of its own
    FeatureTreeModel* m = w->featureModel();
    // Drop the first box onto the union: it moves inside, as a drag does.
    QMimeData* data = m->mimeData({m->indexOf("box")});
    m->dropMimeData(data, Qt::MoveAction, -1, 0, m->indexOf("union"));
    delete data;
    const Node* u = w->session()->document().root.find("union");
    QVERIFY(u);
    QCOMPARE(u->children.size(), std::size_t(2));
    QCOMPARE(u->children.back().id, std::string("box"));
    // Dropping onto a primitive is refused by the model.
    QMimeData* again = m->mimeData({m->indexOf("union")});
    QVERIFY(!m->canDropMimeData(again, Qt::MoveAction, -1, 0, m->indexOf("box")));
    delete again;
    // Visibility through the check box.
    QVERIFY(m->setData(m->indexOf("box"), Qt::Unchecked, Qt::CheckStateRole));
    QVERIFY(!w->session()->document().root.find("box")->visible);
    action(w.get(), "action.undo")->trigger();
    QVERIFY(w->session()->document().root.find("box")->visible);
}

void MainWindowTest::modelsOnlyWhatTheViewNeedsWithinTheBudget()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "side-chair.kerf"));
    QVERIFY(action(w.get(), "action.refineForView")->isChecked());
    QVERIFY(waitForViewport(*w));
    auto deepTilesNear = [&](const glm::dvec3& p, double radius) {
        const auto s = w->voxelizer()->latest();
        int deep = 0;
        for (long i = 0; i < s->layout.tileCount(); ++i) {
            const auto& t = s->tiles[std::size_t(i)];
            if (t && t->state == TileState::Surface && t->levels == s->layout.levels &&
                glm::length(s->layout.tileBox(s->layout.tileCoord(i)).center() - p) < radius)
                ++deep;
        }
        return deep;
    };
    const auto whole = w->voxelizer()->latest();
    // Close up on a corner of the seat: the tiles there refine to full depth,
    // the chair as a whole takes less memory than at full depth everywhere.
    qt::ViewportWidget* v = w->viewport();
    const QPoint centre(v->width() / 2, v->height() / 2);
    const qt::ViewportPick seat = v->pickAt(centre);
    QVERIFY(seat.hit);
    ViewController close = v->view();
    close.zoom(0.08, seat.point);
    v->setView(close);
    QVERIFY(QTest::qWaitFor([&] { return w->voxelizer()->latest()->documentRevision > whole->documentRevision; }, 60000));
    QVERIFY(waitForVoxels(*w));
    const auto near = w->voxelizer()->latest();
    QVERIFY(deepTilesNear(seat.point, 40.0) > 0);
    QVERIFY(near->outsideView > 0);
    const VoxelSnapshot full = voxelize(compileTape(w->session()->document()), near->layout);
    QVERIFY2(near->bytes() < full.bytes(), "the close-up keeps most of the chair coarse");

    // A budget far below the chair at full depth: distant tiles coarsen, the status bar says so.
    w->voxelizer()->voxelizer().setMemoryBudget(8u << 20);
    w->voxelizer()->submit(w->session()->document());
    QVERIFY(waitForVoxels(*w));
    QVERIFY(w->voxelizer()->latest()->coarsenedForBudget > 0);
    QVERIFY(w->voxelizer()->latest()->bytes() < (12u << 20));
    QTRY_VERIFY_WITH_TIMEOUT(w->findChild<QLabel*>("status.memory")->text().contains("coarsened"), 10000);
}

// A plate in front of a ball: seen from the front, the viewport's picture
// tells the voxelizer that the ball is hidden, and its tiles stay coarse;
// turned round, the next pictures show the ball and its tiles refine.
void MainWindowTest::keepsWhatThePartHidesCoarseUntilItShows()
{
    const QString file = files_.filePath("plate-and-ball.kerf");
    {
        QFile f(file);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","children":[
            {"id":"plate","type":"box","size":[160,10,160],"transform":{"translate":[0,-50,0]}},
            {"id":"ball","type":"sphere","radius":20}]},"settings":{"feature_size":0.5}})");
    }
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(file.toStdString()));
    QVERIFY(action(w.get(), "action.refineForView")->isChecked());
    QVERIFY(waitForViewport(*w));
    // The shallowest tile of the ball (beyond y = `from`).
    auto ballLevels = [&](double from = -30.0) {
        const auto s = w->voxelizer()->latest();
        int lo = 99;
        for (long i = 0; i < s->layout.tileCount(); ++i) {
            const auto& t = s->tiles[std::size_t(i)];
            if (t && t->state == TileState::Surface && s->layout.tileBox(s->layout.tileCoord(i)).min.y > from)
                lo = std::min(lo, t->levels);
        }
        return lo;
    };
    // From the front the plate hides the ball: once a picture of that view
    // is taken, an edit of the ball builds its tiles only as deep as the
    // coarse pass.
    QSignalSpy pictures(w->viewport(), &qt::ViewportWidget::pictureTaken);
    w->viewport()->setStandardView("front");
    QVERIFY(waitForVoxels(*w));
    auto pictureOfTheView = [&] {
        if (pictures.isEmpty() || !w->viewport()->settledView()) return false;
        const auto picture = pictures.last().at(0).value<std::shared_ptr<const OcclusionMap>>();
        return picture && picture->view == *w->viewport()->settledView();
    };
    QTRY_VERIFY_WITH_TIMEOUT(pictureOfTheView(), 60000);
    w->selectNodes({"ball"});
    typeInto(field(*w, "radius"), "21");
    QTRY_VERIFY_WITH_TIMEOUT(w->voxelizer()->latest()->hiddenTiles > 0, 60000);
    QVERIFY(waitForViewport(*w));
    const int levels = w->voxelizer()->latest()->layout.levels;
    QVERIFY2(ballLevels() < levels, "the hidden ball stays coarse");
    QTRY_VERIFY_WITH_TIMEOUT(w->findChild<QLabel*>("status.memory")->text().contains("hidden"), 10000);

    // From the back the ball is in sight: its half that faces the camera
    // refines (the far half, behind it, may stay coarse).
    w->viewport()->setStandardView("back");
    QTRY_VERIFY_WITH_TIMEOUT(ballLevels(0.0) == levels, 60000);

    // And then all is quiet: pictures that show nothing new plan nothing, so
    // neither the voxelizer nor the viewport keeps working at rest.
    QVERIFY(waitForViewport(*w));
    QTest::qWait(500);
    const std::uint64_t frames = w->viewport()->status().frames;
    const std::uint64_t version = w->voxelizer()->latest()->version;
    QTest::qWait(1500);
    QCOMPARE(w->voxelizer()->latest()->version, version);
    QCOMPARE(w->viewport()->status().frames, frames);
}

void MainWindowTest::promptsBeforeChangesAreLost()
{
    int asked = 0;
    QMessageBox::StandardButton answer = QMessageBox::Cancel;
    MainWindowOptions options;
    options.askSave = [&](const QString& name) {
        ++asked;
        (void)name;
        return answer;
    };
    auto w = makeWindow(recovery_.path(), options);
    action(w.get(), "action.new")->trigger();
    QCOMPARE(asked, 0); // nothing to lose yet
    action(w.get(), "action.add.torus")->trigger();
    QVERIFY(w->isWindowModified());
    // Cancel: New does nothing, closing does not close.
    action(w.get(), "action.new")->trigger();
    QCOMPARE(asked, 1);
    QVERIFY(w->session()->document().root.find("torus"));
    QVERIFY(!w->close());
    QCOMPARE(asked, 2);
    QVERIFY(w->isVisible());
    // Discard: the new part replaces it.
    answer = QMessageBox::Discard;
    action(w.get(), "action.new")->trigger();
    QCOMPARE(asked, 3);
    QVERIFY(!w->session()->document().root.find("torus"));
    QVERIFY(!w->isWindowModified());
}

void MainWindowTest::dropsDocumentsAndMeshesOntoTheWindow()
{
    auto w = makeWindow(recovery_.path());
    // A .kerf file dropped on the window opens.
    QMimeData doc;
    doc.setUrls({QUrl::fromLocalFile(QString(KERF_EXAMPLES_DIR) + "/table-top.kerf")});
    drop(*w, doc);
    QVERIFY(w->session()->document().root.find("top-slab"));
    // A mesh file becomes a reference mesh of the document (an undoable edit).
    const QString stl = files_.path() + "/knob.stl";
    {
        MeshOptions o;
        o.featureSize = 2.0;
        const auto mesh = meshPart(Document::parse(R"({"format":"kerf","version":1,"root":{"id":"k","type":"sphere","radius":15}})",
                                                   "knob.kerf"),
                                   o);
        QVERIFY(mesh);
        writeStl(*mesh, stl.toStdString());
    }
    QMimeData mesh;
    mesh.setUrls({QUrl::fromLocalFile(stl)});
    drop(*w, mesh);
    QCOMPARE(w->session()->document().meshes.size(), std::size_t(1));
    QCOMPARE(w->session()->document().meshes.front().id, std::string("knob"));
    action(w.get(), "action.undo")->trigger();
    QVERIFY(w->session()->document().meshes.empty());
    // A broken mesh is named and not added.
    const QString broken = files_.path() + "/broken.stl";
    QFile f(broken);
    QVERIFY(f.open(QIODevice::WriteOnly));
    f.write("solid nothing\nendsolid\n");
    f.close();
    QMimeData bad;
    bad.setUrls({QUrl::fromLocalFile(broken)});
    drop(*w, bad);
    QVERIFY(w->session()->document().meshes.empty());
    QVERIFY2(w->lastMessage().contains("broken.stl"), qPrintable(w->lastMessage()));
}

void MainWindowTest::aClickOnThePartSelectsItsFeature()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "stool.kerf"));
    QVERIFY(waitForViewport(*w));
    qt::ViewportWidget* v = w->viewport();
    // A point on the part, found along the middle column.
    QPoint at;
    qt::ViewportPick expected;
    for (int y = v->height() / 4; y < v->height() && !expected.hit; y += 5) {
        at = QPoint(v->width() / 2, y);
        expected = v->pickAt(at);
    }
    QVERIFY(expected.hit);
    // A real click on the drawing surface: the Vulkan window, or the CPU widget.
    QWindow* surface = nullptr;
    for (QWindow* win : QGuiApplication::allWindows())
        if (win->surfaceType() == QSurface::VulkanSurface && win->isVisible()) surface = win;
    if (surface) {
        QTest::mouseClick(surface, Qt::LeftButton, Qt::NoModifier, at);
    } else {
        QWidget* child = v->childAt(at);
        QVERIFY(child);
        QTest::mouseClick(child, Qt::LeftButton, Qt::NoModifier, child->mapFrom(v, at));
    }
    QTRY_COMPARE(w->selectedNodeIds(), std::vector<std::string>{expected.nodeId});
    QCOMPARE(w->propertyEditor()->nodeId(), expected.nodeId);
    // A click on the background clears the selection.
    const QPoint corner(5, 5);
    QVERIFY(!v->pickAt(corner).hit);
    if (surface) QTest::mouseClick(surface, Qt::LeftButton, Qt::NoModifier, corner);
    else QTest::mouseClick(v->childAt(corner), Qt::LeftButton, Qt::NoModifier, corner);
    QTRY_VERIFY(w->selectedNodeIds().empty());
}

void MainWindowTest::aNewBoxStaysOnTheGridWhateverSetsItsHeight()
{
    // A newcomer typed a parameter's name as a new leg's height: the leg
    // stayed centred where the 20 mm box had been, half under the grid,
    // and later plain numbers did not lift it either.
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    const auto bottom = [&] { return nodeBounds(*w->session()->document().root.find("box")).min.z; };
    QCOMPARE(bottom(), 0.0);
    typeInto(field(*w, "size.z"), "=400 + 80");
    QVERIFY2(w->propertyEditor()->errorFor("size.z").isEmpty(), qPrintable(w->propertyEditor()->errorFor("size.z")));
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.z, 480.0);
    QCOMPARE(bottom(), 0.0);
    typeInto(field(*w, "size.z"), "100");
    QCOMPARE(bottom(), 0.0);
    // Lifted by hand, it is the user's place: a new height grows about it.
    typeInto(field(*w, "translate.z"), "200");
    typeInto(field(*w, "size.z"), "50");
    QCOMPARE(w->session()->document().root.find("box")->transform.translate.z, 200.0);

    // A panel whose thickness is a parameter stays on the grid when the
    // parameter changes: a newcomer's stayed centred at 9 mm when thickness
    // went from 18 to 25, and the cuts measured from its top came out shallower.
    action(w.get(), "action.new")->trigger();
    auto* panel = w->findChild<ParametersPanel*>("parametersPanel");
    panel->addParameter();
    if (auto* open = panel->table()->findChild<QLineEdit*>()) QTest::keyClick(open, Qt::Key_Escape);
    const std::string thickness = w->session()->document().parameters.at(0).name;
    panel->table()->item(0, ParametersPanel::ExpressionColumn)->setText("18");
    action(w.get(), "action.add.box")->trigger();
    typeInto(field(*w, "size.z"), QString::fromStdString("=" + thickness));
    QCOMPARE(bottom(), 0.0);
    QCOMPARE(w->session()->document().root.find("box")->expressions.at("transform.translate[2]"), thickness + "/2");
    panel->table()->item(0, ParametersPanel::ExpressionColumn)->setText("25");
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.z, 25.0);
    QCOMPARE(bottom(), 0.0);
}

void MainWindowTest::escapeInAFieldTakesBackWhatWasTyped()
{
    // A newcomer typed into a field, thought better of it and pressed Esc:
    // the typed text stayed, and went into the part when the field was left.
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    typeInto(field(*w, "size.x"), "600");
    const Document before = w->session()->document();
    const int steps = w->session()->undoStack()->count();
    QuantityEdit* x = field(*w, "size.x");
    x->setFocus();
    x->selectAll();
    QTest::keyClicks(x, "999");
    QTest::keyClick(x, Qt::Key_Escape);
    QCOMPARE(x->text(), QString("600 mm"));
    field(*w, "size.y")->setFocus(); // leaving the field enters nothing
    QCOMPARE(w->session()->document(), before);
    QCOMPARE(w->session()->undoStack()->count(), steps);
    // A field set by an expression gets its expression back.
    typeInto(x, "=300 * 2 + 10");
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, 610.0);
    x->setFocus();
    x->selectAll();
    QTest::keyClicks(x, "5");
    QTest::keyClick(x, Qt::Key_Escape);
    QCOMPARE(x->text(), QString("=300 * 2 + 10"));
    field(*w, "size.y")->setFocus();
    QCOMPARE(w->session()->document().root.find("box")->expressions.at("size[0]"), std::string("300 * 2 + 10"));
    QCOMPARE(w->session()->document().root.find("box")->as<BoxParams>().size.x, 610.0);

    // So in the Name field: nothing renamed on leaving it.
    w->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(w.get())); // focus and shortcuts live in the active window
    auto* name = w->propertyEditor()->findChild<QLineEdit*>("field.name");
    QVERIFY(name);
    name->setFocus();
    QTRY_VERIFY(name->hasFocus());
    name->selectAll();
    QTest::keyClicks(name, "Side XYZ");
    QTest::keyClick(name, Qt::Key_Escape);
    QCOMPARE(name->text(), QString());
    field(*w, "size.y")->setFocus();
    QVERIFY(!w->session()->document().root.find("box")->name);
}

void MainWindowTest::aNewPartIsSavedWithItsParametersBeforeItsFirstFeature()
{
    // A newcomer set up a drawer's parameters first: their values showed 0
    // and Save said "an union needs at least 1 child".
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    auto* panel = w->findChild<ParametersPanel*>("parametersPanel");
    panel->addParameter();
    if (auto* open = panel->table()->findChild<QLineEdit*>()) QTest::keyClick(open, Qt::Key_Escape);
    panel->table()->item(0, ParametersPanel::ExpressionColumn)->setText("500mm");
    QCOMPARE(w->session()->document().parameters.at(0).value, 500.0);
    QCOMPARE(panel->table()->item(0, ParametersPanel::ValueColumn)->text(), QString("500"));
    const QString file = files_.path() + "/drawer.kerf";
    QVERIFY2(w->saveAs(file.toStdString()), qPrintable(w->lastMessage()));
    const Document saved = Document::load(file.toStdString());
    QVERIFY(saved.root.children.empty());
    QCOMPARE(saved.parameters.at(0).expression, std::string("500mm"));
    QVERIFY(w->openFile(file.toStdString()));
    QCOMPARE(w->session()->document().parameters.at(0).value, 500.0);
}

// A file with a misspelt field ("transfom") opens, as the format keeps
// fields it does not know, and the leg stands where no transform puts it:
// the status bar names the field and the one it probably means, until the
// part is next changed.
void MainWindowTest::aMisspeltFieldIsNamedOnOpening()
{
    const QString doc = files_.path() + "/misspelt.kerf";
    QVERIFY(writeTestFile(doc, R"({"format":"kerf","version":1,"root":{"id":"top","type":"union","children":[
        {"id":"board","type":"box","size":[300,200,18]},
        {"id":"leg","type":"cylinder","radius":15,"height":450,"transfom":{"translate":[0,0,-225]}}]}})"));
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(doc.toStdString()));
    const QString message = w->statusBar()->currentMessage();
    QVERIFY2(message == "Opened misspelt.kerf, but 'transfom' in feature 'leg' is no field Kerf knows (did you mean "
                        "'transform'?), kept but not used",
             qPrintable(message));
    QVERIFY(waitForViewport(*w));
    saveWidgetShot(*w, "misspelt-field-on-opening");
    QCOMPARE(w->statusBar()->currentMessage(), message); // the view's build does not push it out
    w->selectNodes({"board"});
    typeInto(field(*w, "size.x"), "320");
    QVERIFY2(!w->statusBar()->currentMessage().contains("transfom"), qPrintable(w->statusBar()->currentMessage()));
    // Saved again, the field is kept as it was written.
    QVERIFY(w->saveAs(doc.toStdString()));
    QFile saved(doc);
    QVERIFY(saved.open(QIODevice::ReadOnly));
    QVERIFY(saved.readAll().contains("\"transfom\""));
}

void MainWindowTest::aFileThatIsNoKerfDocumentIsRefusedBeforeAskingToSave()
{
    // A newcomer opened a PNG: asked first whether to save the changes,
    // then told "malformed JSON ... last read: '\x89'".
    int asked = 0;
    MainWindowOptions options;
    options.askSave = [&](const QString&) {
        ++asked;
        return QMessageBox::Cancel;
    };
    auto w = makeWindow(recovery_.path(), options);
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    const Document before = w->session()->document();
    const QString png = files_.path() + "/picture.kerf";
    QVERIFY(writeTestFile(png, QByteArray("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16)));
    QVERIFY(!w->openFile(png.toStdString()));
    QCOMPARE(asked, 0);
    QCOMPARE(w->session()->document(), before);
    QVERIFY2(w->lastMessage().contains("not a Kerf document") && w->lastMessage().contains("is a PNG image"),
             qPrintable(w->lastMessage()));
    // The refusal stays in the status bar until the part is next changed.
    QCOMPARE(w->statusBar()->currentMessage(), w->lastMessage());
    typeInto(field(*w, "size.x"), "30");
    QVERIFY2(!w->statusBar()->currentMessage().contains("not a Kerf document"),
             qPrintable(w->statusBar()->currentMessage()));
}

void MainWindowTest::deletingAMirroredLegTakesTheEmptiedMirrorAlong()
{
    // A newcomer deleted the leg under a mirror and was refused: "a mirror
    // needs at least 1 child", with no way on but finding the mirror.
    const QString doc = files_.path() + "/mirrored.kerf";
    QVERIFY(writeTestFile(doc, R"({"format":"kerf","version":1,"root":{"id":"root","type":"union","children":[
            {"id":"top","type":"box","size":[100,100,18]},
            {"id":"m","type":"mirror","normal":[1,0,0],"offset":0,"children":[
                {"id":"leg","type":"box","name":"Leg","size":[10,10,100],"transform":{"translate":[40,0,50]}}]}]}})"));
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(doc.toStdString()));
    const Document before = w->session()->document();
    w->selectNodes({"leg"});
    action(w.get(), "action.delete")->trigger();
    QCOMPARE(w->session()->document().root.find("leg"), nullptr);
    QCOMPARE(w->session()->document().root.find("m"), nullptr);
    QVERIFY(w->session()->document().root.find("top"));
    QVERIFY2(w->lastMessage().startsWith("Delete Leg and the mirror, left empty"), qPrintable(w->lastMessage()));
    QCOMPARE(w->session()->undoStack()->undoText(), QString("Delete Leg and the mirror, left empty"));
    w->session()->undoStack()->undo();
    QCOMPARE(w->session()->document(), before);
    // The deletion undone comes back open in the tree, the leg in sight
    // (it came back closed, as a feature never opened).
    QVERIFY(w->featureTree()->isExpanded(w->featureModel()->indexOf("m")));

    // A grooved side under a mirror: deleting the side asks about its
    // groove's difference; "too" takes the difference, and the mirror it
    // leaves empty goes with it (the answer was once refused afterwards).
    const QString grooved = files_.path() + "/grooved.kerf";
    QVERIFY(writeTestFile(grooved, R"({"format":"kerf","version":1,"root":{"id":"root","type":"union","children":[
            {"id":"front","type":"box","size":[600,18,150]},
            {"id":"sides","type":"mirror","normal":[1,0,0],"offset":0,"children":[
                {"id":"side-d","type":"difference","name":"Left side with groove","children":[
                    {"id":"side","type":"box","name":"Left side","size":[12,450,150],"transform":{"translate":[294,225,75]}},
                    {"id":"groove","type":"box","size":[6,450,6],"transform":{"translate":[291,225,13]}}]}]}]}})"));
    QVERIFY(w->openFile(grooved.toStdString()));
    w->selectNodes({"side"});
    {
        MessageBoxAnswerer answer("delete.base.whole");
        action(w.get(), "action.delete")->trigger();
        QVERIFY(answer.answered());
    }
    QCOMPARE(w->session()->document().root.find("sides"), nullptr);
    QVERIFY(w->session()->document().root.find("front"));
    QCOMPARE(w->session()->undoStack()->undoText(), QString("Delete Left side with groove and the mirror, left empty"));
}

void MainWindowTest::aMirrorTurnsToAnotherAxisInOneClick()
{
    // From X to Y one field at a time passes through (0, 0, 0), which is
    // refused: a newcomer had to find that Y goes first.
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.box")->trigger();
    action(w.get(), "action.group.mirror")->trigger();
    const std::vector<std::string> selected = w->selectedNodeIds();
    QCOMPARE(selected.size(), std::size_t(1));
    const auto normal = [&] { return w->session()->document().root.find(selected.front())->as<MirrorParams>().normal; };
    QCOMPARE(normal(), glm::dvec3(1, 0, 0));
    auto* alongY = w->propertyEditor()->findChild<QPushButton*>("field.normal.along.y");
    QVERIFY(alongY);
    QTest::mouseClick(alongY, Qt::LeftButton);
    QCOMPARE(normal(), glm::dvec3(0, 1, 0));
    QVERIFY2(w->session()->undoStack()->undoText().startsWith("Set normal of the mirror along Y"),
             qPrintable(w->session()->undoStack()->undoText()));
    QCOMPARE(field(*w, "normal.x")->value(), 0.0);
    QCOMPARE(field(*w, "normal.y")->value(), 1.0);
    QTest::mouseClick(w->propertyEditor()->findChild<QPushButton*>("field.normal.along.z"), Qt::LeftButton);
    QCOMPARE(normal(), glm::dvec3(0, 0, 1));
}

void MainWindowTest::theGizmoLeavesACoordinateSetByAnExpression()
{
    // A newcomer dragged a leg whose height on the frame was an expression:
    // the drag replaced it with a number without a word. A coordinate set
    // by an expression now stays, and the status bar says why.
    auto w = makeWindow(recovery_.path());
    qt::ViewportWidget* v = selectTheFirstShelfPinHole(*w);
    QVERIFY(v);
    typeInto(field(*w, "translate.z"), "=150 + 10");
    const auto find = [&] { return w->session()->document().root.find("shelf-pin-hole"); };
    QCOMPARE(find()->transform.translate.z, 160.0);
    QTRY_VERIFY(v->moveGizmo().has_value());
    QTRY_COMPARE(v->moveGizmoOrigin()->z, 160.0);
    const Surface surface(v);
    const MoveGizmo g = *v->moveGizmo();
    const glm::dvec3 grip = g.origin + 0.7 * g.armLength * glm::dvec3(0, 0, 1);
    surface.press(surface.at(grip));
    for (double dz : {5.0, 12.0, 20.0}) surface.move(surface.at(grip + glm::dvec3(0, 0, dz)));
    QVERIFY2(w->lastMessage().contains("stays where it is: its Z is set by =150 + 10. Change that in the Properties."),
             qPrintable(w->lastMessage()));
    surface.release(surface.at(grip + glm::dvec3(0, 0, 20.0)));
    QCOMPARE(find()->transform.translate.z, 160.0);
    QCOMPARE(find()->expressions.at("transform.translate[2]"), std::string("150 + 10"));
}

void MainWindowTest::aPartThinnerThanAVoxelEverywhereIsSaidNotLeftBlank()
{
    // A newcomer typed 2000 into an array's count: the part became 100 m
    // long, its view feature size 100 mm, its 40 mm legs thinner than a
    // voxel, and the view went blank without a word.
    const QString doc = files_.path() + "/long.kerf";
    {
        QFile f(doc);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","children":[
            {"id":"legs","type":"array","count":[2000,1,1],"step":[50,0,0],"children":[
                {"id":"leg","type":"box","size":[40,40,40]}]}]}})");
    }
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(doc.toStdString()));
    QTRY_VERIFY_WITH_TIMEOUT(w->statusBar()->currentMessage().startsWith("Nothing shows at the view feature size of"),
                             60000);
    QVERIFY2(w->statusBar()->currentMessage().contains("a finer View feature size in Properties"),
             qPrintable(w->statusBar()->currentMessage()));
    // At the part's own voxel size (it said "0 mm", from the empty part
    // shown before the file opened).
    QVERIFY2(w->statusBar()->currentMessage().startsWith("Nothing shows at the view feature size of 50 mm"),
             qPrintable(w->statusBar()->currentMessage()));
    // Done so, the legs show and the message goes.
    w->selectNodes({});
    typeInto(w->propertyEditor()->findChild<QuantityEdit*>("part.featureSize"), "10");
    QTRY_VERIFY_WITH_TIMEOUT(!w->statusBar()->currentMessage().startsWith("Nothing shows"), 120000);
}

void MainWindowTest::keyFiveInTheViewMovesTheOrthographicCheckMark()
{
    // A newcomer turned Orthographic on in the View menu, pressed 5 in the
    // view: the view went back to perspective, the toolbar still said
    // Orthographic.
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "stool.kerf"));
    QVERIFY(waitForViewport(*w));
    qt::ViewportWidget* v = w->viewport();
    QAction* ortho = action(w.get(), "action.orthographic");
    ortho->trigger();
    QVERIFY(ortho->isChecked());
    QVERIFY(v->orthographic());
    const Surface surface(v);
    surface.click(QPoint(3, 3)); // the view has the keyboard
    surface.key(Qt::Key_5);
    QTRY_VERIFY(!v->orthographic());
    QVERIFY(!ortho->isChecked());
    surface.key(Qt::Key_5);
    QTRY_VERIFY(v->orthographic());
    QVERIFY(ortho->isChecked());
}

void MainWindowTest::theViewKeysAnswerWithTheFeatureTreeInFocus()
{
    // A newcomer clicked a feature in the tree and pressed 1: nothing (the
    // keys answered only in the view). In a table, a digit still edits.
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side-parametric.kerf"));
    w->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(w.get())); // shortcuts answer in the active window
    qt::ViewportWidget* v = w->viewport();
    action(w.get(), "action.view.front")->trigger();
    const double frontYaw = v->view().yawDegrees(), frontPitch = v->view().pitchDegrees();
    action(w.get(), "action.view.iso")->trigger();
    QVERIFY(v->view().yawDegrees() != frontYaw || v->view().pitchDegrees() != frontPitch);
    clickRow(*w, "panel");
    auto* tree = w->findChild<QTreeView*>("featureTree");
    QVERIFY(tree && tree->hasFocus());
    QTest::keyClick(tree, Qt::Key_1);
    QCOMPARE(v->view().yawDegrees(), frontYaw);
    QCOMPARE(v->view().pitchDegrees(), frontPitch);
    // The opposite views on Ctrl and the same key: back, left, bottom (they
    // had no key), each as its menu entry puts it.
    for (const auto& [key, name] : {std::pair{Qt::Key_1, "back"}, std::pair{Qt::Key_3, "left"},
                                    std::pair{Qt::Key_7, "bottom"}}) {
        action(w.get(), QString("action.view.") + name)->trigger();
        const double yaw = v->view().yawDegrees(), pitch = v->view().pitchDegrees();
        action(w.get(), "action.view.iso")->trigger();
        QTest::keyClick(tree, key, Qt::ControlModifier);
        QCOMPARE(v->view().yawDegrees(), yaw);
        QCOMPARE(v->view().pitchDegrees(), pitch);
    }

    // In the Parameters table a digit starts editing the cell, as typing does.
    action(w.get(), "action.view.iso")->trigger();
    auto* table = w->findChild<ParametersPanel*>("parametersPanel")->table();
    table->setFocus();
    table->setCurrentCell(0, ParametersPanel::ExpressionColumn);
    QTest::keyClick(table, Qt::Key_1);
    auto* editor = table->findChild<QLineEdit*>();
    QVERIFY(editor && editor->isVisible());
    QCOMPARE(editor->text(), QString("1"));
    QVERIFY(v->view().yawDegrees() != frontYaw || v->view().pitchDegrees() != frontPitch);
    if (auto* open = table->findChild<QLineEdit*>()) QTest::keyClick(open, Qt::Key_Escape);

    // So in a turned profile's point table.
    action(w.get(), "action.add.revolve")->trigger();
    auto* points = w->propertyEditor()->findChild<QTableWidget*>("field.profile");
    QVERIFY(points);
    QTRY_VERIFY(points->isVisible());
    points->setFocus();
    QTRY_VERIFY(points->hasFocus());
    points->setCurrentCell(0, 0);
    QTest::keyClick(points, Qt::Key_1);
    auto* pointEditor = points->findChild<QLineEdit*>();
    QVERIFY(pointEditor && pointEditor->isVisible());
    QCOMPARE(pointEditor->text(), QString("1"));
    QVERIFY(v->view().yawDegrees() != frontYaw || v->view().pitchDegrees() != frontPitch);
    QTest::keyClick(pointEditor, Qt::Key_Escape);
}

void MainWindowTest::measuringSnapsToHoleCentresAndDrawsTheDimension()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side.kerf"));
    QVERIFY(waitForViewport(*w));
    qt::ViewportWidget* v = w->viewport();
    lookAtTheFirstHoles(*v);
    const Surface surface(v);
    // Turning measuring on says what to do, in the status bar and the Measure panel (shown).
    surface.click(QPoint(3, 3)); // the viewport has the keyboard, as after any click in it
    // (M on the keyboard is a window-wide shortcut: QTest's keys reach the
    // Vulkan window without passing the shortcut map, so the action here.)
    action(w.get(), "action.measure")->trigger();
    QVERIFY(action(w.get(), "action.measure")->isChecked());
    QVERIFY2(w->lastMessage().contains("click two points"), qPrintable(w->lastMessage()));
    QVERIFY(w->measureText().contains("hole centres"));
    QVERIFY(!w->findChild<QDockWidget*>("dock.measure")->visibleRegion().isEmpty());
    // A click a few pixels outside each hole's rim, on the face: the hole's centre.
    const QPoint offset(4, 2);
    surface.click(surface.at(glm::dvec3(9, 37 + 2.5, 160)) + offset);
    QVERIFY2(w->measureText().contains("centre (9.00, 37.00, 160.00)"), qPrintable(w->measureText()));
    surface.click(surface.at(glm::dvec3(9, 37 + 2.5, 192)) + offset);
    QVERIFY2(w->measureText().contains("Distance: 32.00 mm"), qPrintable(w->measureText()));
    QVERIFY(w->measureText().contains("to centre (9.00, 37.00, 192.00)"));
    QCOMPARE(v->dimensionText(), QString("32.00 mm"));
    auto* label = v->findChild<QLabel*>("viewport.dimension");
    QVERIFY(label && label->isVisible());
    // Beside the line, between the two holes.
    const QPoint mid = surface.at(glm::dvec3(9, 37, 176));
    QVERIFY2(std::abs(label->geometry().center().y() - mid.y()) < 60, qPrintable(QString::number(label->y())));
    saveScreenshot(*w, "measure-dimension");
    // Measuring off: the dimension stays; Esc in the view clears it.
    action(w.get(), "action.measure")->trigger();
    QVERIFY(!action(w.get(), "action.measure")->isChecked());
    QCOMPARE(v->dimensionText(), QString("32.00 mm"));
    surface.key(Qt::Key_Escape);
    QTRY_VERIFY(v->dimensionText().isEmpty());
    QVERIFY(!label->isVisible());
}

void MainWindowTest::theGizmoMovesAHoleBySnappedOrTypedDistancesInOneUndoStep()
{
    auto w = makeWindow(recovery_.path());
    qt::ViewportWidget* v = selectTheFirstShelfPinHole(*w);
    QVERIFY(v);
    QTRY_VERIFY(v->moveGizmo().has_value());
    // On the hole's first copy: x from -3 to 10, centred on y 37, z 160.
    QCOMPARE(v->moveGizmoOrigin()->z, 160.0);
    const auto z = [&] { return w->session()->document().root.find("shelf-pin-hole")->transform.translate.z; };
    const Surface surface(v);
    QUndoStack* undo = w->session()->undoStack();
    const int steps = undo->count();

    // Drag the Z arrow (seen from +X it points up the screen) by about 31.6 mm.
    const MoveGizmo g = *v->moveGizmo();
    const glm::dvec3 grip = g.origin + 0.7 * g.armLength * glm::dvec3(0, 0, 1);
    surface.press(surface.at(grip));
    for (double dz : {5.0, 12.0, 20.0, 27.0, 31.6}) surface.move(surface.at(grip + glm::dvec3(0, 0, dz)));
    QVERIFY2(w->lastMessage().contains("along Z"), qPrintable(w->lastMessage()));
    surface.release(surface.at(grip + glm::dvec3(0, 0, 31.6)));
    QCOMPARE(z(), 192.0); // snapped: 32 mm exactly
    QCOMPARE(undo->count(), steps + 1); // one step for the whole drag
    QVERIFY2(undo->undoText().contains("32 mm along Z"), qPrintable(undo->undoText()));
    QTRY_COMPARE(v->moveGizmoOrigin()->z, 192.0); // the gizmo follows
    undo->undo();
    QCOMPARE(z(), 160.0);
    undo->redo();
    QCOMPARE(z(), 192.0);

    // A distance typed during the drag is taken exactly, whatever the mouse did.
    const MoveGizmo g2 = *v->moveGizmo();
    const glm::dvec3 grip2 = g2.origin + 0.7 * g2.armLength * glm::dvec3(0, 0, 1);
    surface.press(surface.at(grip2));
    surface.move(surface.at(grip2 + glm::dvec3(0, 0, 7.0)));
    surface.keys("-48.5");
    surface.key(Qt::Key_Return);
    QCOMPARE(z(), 143.5);
    surface.release(surface.at(grip2 + glm::dvec3(0, 0, 7.0)));
    QCOMPARE(z(), 143.5);
    QCOMPARE(undo->count(), steps + 2);

    // Esc during a drag puts the hole back and leaves no step, and Redo
    // keeps what it had (the drag's first move once cleared it).
    undo->undo();
    QCOMPARE(z(), 192.0);
    QVERIFY(undo->canRedo());
    QTRY_COMPARE(v->moveGizmoOrigin()->z, 192.0);
    const MoveGizmo g3 = *v->moveGizmo();
    const glm::dvec3 grip3 = g3.origin + 0.7 * g3.armLength * glm::dvec3(0, 0, 1);
    // (Down the screen: the view shows z 152 to 200, and without Vulkan the
    // events go to the widget under the pointer.)
    surface.press(surface.at(grip3));
    surface.move(surface.at(grip3 - glm::dvec3(0, 0, 20.0)));
    QVERIFY(z() != 192.0);
    surface.key(Qt::Key_Escape);
    surface.release(surface.at(grip3 - glm::dvec3(0, 0, 20.0)));
    QCOMPARE(z(), 192.0);
    QCOMPARE(undo->count(), steps + 2);
    QVERIFY(undo->canRedo());
    undo->redo();
    QCOMPARE(z(), 143.5);
    QTRY_COMPARE(v->moveGizmoOrigin()->z, 143.5);

    // A drag that starts off the gizmo orbits the camera and moves nothing.
    const glm::dvec3 eye = v->view().camera(100, 100, Aabb{glm::dvec3(-1), glm::dvec3(1)}).eye();
    surface.press(surface.at(grip3) + QPoint(150, 0));
    surface.move(surface.at(grip3) + QPoint(190, 20));
    surface.release(surface.at(grip3) + QPoint(190, 20));
    QCOMPARE(z(), 143.5);
    QVERIFY(v->view().camera(100, 100, Aabb{glm::dvec3(-1), glm::dvec3(1)}).eye() != eye);
    saveScreenshot(*w, "move-gizmo");

    // Lengths shown in inches: a typed distance is inches, fractions too.
    action(w.get(), "action.lengths.in")->trigger();
    const MoveGizmo g4 = *v->moveGizmo();
    const glm::dvec3 grip4 = g4.origin + 0.7 * g4.armLength * glm::dvec3(0, 0, 1);
    surface.press(surface.at(grip4));
    surface.move(surface.at(grip4 + glm::dvec3(0, 0, 7.0)));
    surface.keys("1 1/2");
    QVERIFY2(w->lastMessage().contains("typed: 1 1/2\", Enter"), qPrintable(w->lastMessage()));
    surface.key(Qt::Key_Return);
    surface.release(surface.at(grip4 + glm::dvec3(0, 0, 7.0)));
    QCOMPARE(z(), 143.5 + 38.1);
    QVERIFY2(undo->undoText().contains("1 1/2\" along Z"), qPrintable(undo->undoText()));
    action(w.get(), "action.lengths.mm")->trigger();
}

void MainWindowTest::aSelectedHoleShowsItsToolBodyAsAGhost()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side.kerf"));
    QVERIFY(waitForViewport(*w));
    qt::ViewportWidget* v = w->viewport();
    lookAtTheFirstHoles(*v);
    const QImage plain = v->grabFrame();
    clickRow(*w, "shelf-pin-hole");
    QTRY_VERIFY_WITH_TIMEOUT(!w->ghostsBusy(), 60000);
    QVERIFY(v->hasGhosts());
    const QImage ghost = v->grabFrame();
    // Over the hole's opening the picture turns blue: the tool body, seen through.
    const Surface surface(v);
    const double dpr = v->devicePixel(QPointF(1, 0)).x - v->devicePixel(QPointF(0, 0)).x;
    // Inside the opening, away from the gizmo's arrows (they point to +X, +Y and +Z).
    const QPoint hole = surface.at(glm::dvec3(9, 37 - 1.3, 160 - 1.3)) * dpr;
    const QColor before = plain.pixelColor(hole), after = ghost.pixelColor(hole);
    QVERIFY2(after.blue() > before.blue() + 30 && after.blue() > after.red(),
             qPrintable(QString("%1 -> %2 at %3, %4 of %5 x %6")
                            .arg(before.name(), after.name())
                            .arg(hole.x())
                            .arg(hole.y())
                            .arg(ghost.width())
                            .arg(ghost.height())));
    // An edit elsewhere in the part leaves the hole's body as it is: not meshed again.
    QVERIFY(w->session()->apply("Move the notch", [](Document& d) { d.root.find("toe-kick")->transform.translate.z += 5; }));
    QVERIFY(!w->ghostsBusy());
    QVERIFY(v->hasGhosts());
    // Moving the hole itself does remesh it.
    QVERIFY(w->session()->apply("Move the hole",
                                [](Document& d) { d.root.find("shelf-pin-hole")->transform.translate.z += 5; }));
    QVERIFY(w->ghostsBusy());
    QTRY_VERIFY_WITH_TIMEOUT(!w->ghostsBusy() && v->hasGhosts(), 60000);
    // A gizmo drag moves the hole at every mouse move, each while the last
    // is still being meshed. The ghost follows during the drag: each move
    // once cancelled the mesh under way, and the ghost stayed where the
    // drag began until the button was let go.
    auto* ghosts = w->findChild<SelectionGhosts*>();
    QVERIFY(ghosts);
    const double startZ = v->ghostBounds().min.z;
    QSignalSpy shown(ghosts, &SelectionGhosts::shown);
    auto moveUp = [](Document& d) { d.root.find("shelf-pin-hole")->transform.translate.z += 2; };
    QVERIFY(w->session()->apply("Move the hole", moveUp));
    QVERIFY(w->session()->apply("Move the hole", moveUp));
    QTRY_VERIFY_WITH_TIMEOUT(shown.count() >= 1, 60000);
    QVERIFY2(std::abs(v->ghostBounds().min.z - (startZ + 2)) < 0.5, qPrintable(QString::number(v->ghostBounds().min.z - startZ)));
    QVERIFY(w->ghostsBusy()); // the second move's ghost, under way
    QTRY_VERIFY_WITH_TIMEOUT(!w->ghostsBusy(), 60000);
    QCOMPARE(shown.count(), 2);
    QVERIFY2(std::abs(v->ghostBounds().min.z - (startZ + 4)) < 0.5, qPrintable(QString::number(v->ghostBounds().min.z - startZ)));
    // The panel is not a tool: no ghost.
    clickRow(*w, "panel");
    QTRY_VERIFY_WITH_TIMEOUT(!w->ghostsBusy() && !v->hasGhosts(), 60000);
    // The array of holes is a tool too: every copy is drawn.
    clickRow(*w, "shelf-pin-holes");
    QTRY_VERIFY_WITH_TIMEOUT(!w->ghostsBusy() && v->hasGhosts(), 60000);
}

void MainWindowTest::theBoundingBoxOfTheSelectionIsMeasuredAndDrawn()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side.kerf"));
    QVERIFY(waitForViewport(*w));
    clickRow(*w, "toe-kick");
    action(w.get(), "action.boundingBox")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(w->measureText().startsWith("Bounding box of Toe kick notch: 20.00 x 61.00 x 71.00 mm"),
                             30000);
    QCOMPARE(w->viewport()->dimensionText(), QString("20.00 x 61.00 x 71.00 mm"));
    // Nothing selected: the part's.
    w->selectNodes({});
    action(w.get(), "action.boundingBox")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(w->measureText().startsWith("Bounding box: 18.00 x 300.00 x 1800.00 mm"), 30000);
    QCOMPARE(w->viewport()->dimensionText(), QString("18.00 x 300.00 x 1800.00 mm"));
}

void MainWindowTest::deleteInTheParametersTableIsTheParametersNotTheFeatures()
{
    // A newcomer selected the table top in the tree, clicked a parameter's
    // row and pressed Delete: the table top went, the parameter stayed.
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side-parametric.kerf"));
    w->show();
    QVERIFY(QTest::qWaitForWindowExposed(w.get()));
    w->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(w.get()));
    w->selectNodes({"panel"});
    auto* panel = w->findChild<ParametersPanel*>("parametersPanel");
    QTableWidget* table = panel->table();
    const Document before = w->session()->document();
    // A parameter in use: refused beside the table, and no feature goes.
    table->setFocus();
    table->setCurrentCell(0, ParametersPanel::NameColumn);
    QTest::keyClick(table, Qt::Key_Delete);
    QVERIFY(w->session()->document() == before);
    QVERIFY2(panel->error().contains("thickness"), qPrintable(panel->error()));
    // An unused one goes, in one undo step; the features stay.
    panel->addParameter();
    QTRY_VERIFY(table->findChild<QLineEdit*>() != nullptr);
    QTest::keyClick(table->findChild<QLineEdit*>(), Qt::Key_Escape);
    const std::size_t count = w->session()->document().parameters.size();
    table->setFocus();
    table->setCurrentCell(int(count) - 1, ParametersPanel::NameColumn);
    QTest::keyClick(table, Qt::Key_Delete);
    QCOMPARE(w->session()->document().parameters.size(), count - 1);
    QVERIFY(w->session()->document().root == before.root);
    // In the tree, Delete is still the feature's (the panel is what the
    // part cuts from: asked first, and cancelled).
    w->featureTree()->setFocus();
    {
        MessageBoxAnswerer cancel("delete.base.cancel");
        QTest::keyClick(w->featureTree(), Qt::Key_Delete);
        QVERIFY(cancel.answered());
    }
    QVERIFY(w->session()->document().root == before.root);
}

// A newcomer typed a long formula with one misspelt name into the
// Parameters table: it was refused under the table and the cell went back
// to the old expression, the typing lost. Now the cell's editor opens
// again on what was typed (the cell itself shows the document), to mend;
// mended, it is applied; Esc gives it up with its message.
void MainWindowTest::aRefusedFormulaOpensAgainToMend()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side-parametric.kerf"));
    auto* panel = w->findChild<ParametersPanel*>("parametersPanel");
    QTableWidget* table = panel->table();
    int row = -1;
    for (int r = 0; r < table->rowCount(); ++r)
        if (table->item(r, ParametersPanel::NameColumn)->text() == "height") row = r;
    QVERIFY(row >= 0);
    const QModelIndex index = table->model()->index(row, ParametersPanel::ExpressionColumn);
    auto typeAndReturn = [&](const QString& text) {
        table->setCurrentIndex(index);
        table->edit(index);
        auto* editor = qobject_cast<QLineEdit*>(table->indexWidget(index));
        QVERIFY(editor);
        editor->setText(text);
        QTest::keyClick(editor, Qt::Key_Return);
    };
    const Document before = w->session()->document();
    typeAndReturn("thicknes*100");
    // (The delegate commits a Return in a queued call.)
    QTRY_VERIFY2(panel->error().contains("uses the unknown name 'thicknes': did you mean 'thickness'?"),
                 qPrintable(panel->error()));
    QCOMPARE(table->item(row, ParametersPanel::ExpressionColumn)->text(), QString("1800mm")); // the document's
    QVERIFY(w->session()->document() == before);
    QTRY_VERIFY(qobject_cast<QLineEdit*>(table->indexWidget(index)));
    QCOMPARE(qobject_cast<QLineEdit*>(table->indexWidget(index))->text(), QString("thicknes*100"));
    saveScreenshot(*w, "parameters-refused-formula-to-mend");

    // Mended in the editor it opened: applied, the message gone.
    auto* editor = qobject_cast<QLineEdit*>(table->indexWidget(index));
    editor->setText("thickness*100");
    QTest::keyClick(editor, Qt::Key_Return);
    QTRY_COMPARE(table->item(row, ParametersPanel::ExpressionColumn)->text(), QString("thickness*100"));
    QVERIFY2(panel->error().isEmpty(), qPrintable(panel->error()));
    const auto height = std::find_if(w->session()->document().parameters.begin(),
                                     w->session()->document().parameters.end(),
                                     [](const Parameter& p) { return p.name == "height"; });
    QCOMPARE(height->value, 1800.0);

    // Refused again, then given up with Esc: the editor and its message go.
    typeAndReturn("thicknes*100");
    QTRY_VERIFY(qobject_cast<QLineEdit*>(table->indexWidget(index)));
    QTest::keyClick(qobject_cast<QLineEdit*>(table->indexWidget(index)), Qt::Key_Escape);
    QTRY_VERIFY(!table->indexWidget(index));
    QVERIFY2(panel->error().isEmpty(), qPrintable(panel->error()));
    QCOMPARE(table->item(row, ParametersPanel::ExpressionColumn)->text(), QString("thickness*100"));
}

void MainWindowTest::theThicknessChangedInTheParametersPanelCarriesEveryDependentFeature()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side-parametric.kerf"));
    auto* panel = w->findChild<ParametersPanel*>("parametersPanel");
    QVERIFY(panel);
    QTableWidget* table = panel->table();
    QCOMPARE(table->rowCount(), 6);
    QCOMPARE(table->item(0, ParametersPanel::NameColumn)->text(), QString("thickness"));
    QCOMPARE(table->item(0, ParametersPanel::ValueColumn)->text(), QString("18 mm"));
    // Where it is used, as the Properties name it (not "panel.size[0]").
    QVERIFY2(table->item(0, ParametersPanel::NameColumn)->toolTip().startsWith("Used by Size X of "),
             qPrintable(table->item(0, ParametersPanel::NameColumn)->toolTip()));
    auto panelThickness = [&] { return w->session()->document().root.find("panel")->as<BoxParams>().size.x; };
    auto dadoX = [&] { return w->session()->document().root.find("dado-bottom")->transform.translate.x; };

    // The person types 3/4in over the thickness's expression, as they would (the table's editor).
    table->setCurrentCell(0, ParametersPanel::ExpressionColumn);
    table->editItem(table->item(0, ParametersPanel::ExpressionColumn));
    auto* editor = table->findChild<QLineEdit*>();
    QVERIFY(editor);
    editor->selectAll();
    QTest::keyClicks(editor, "3/4in");
    QTest::keyClick(editor, Qt::Key_Return);
    QTRY_COMPARE(panelThickness(), 19.05);
    QCOMPARE(dadoX(), 19.05 / 2 - 8 + 4.5); // the dado keeps its depth from the face
    QCOMPARE(w->session()->document().root.find("back-groove")->transform.translate.x, 19.05 / 2 - 9 + 5);
    QCOMPARE(table->item(0, ParametersPanel::ValueColumn)->text(), QString("19.05 mm"));
    QVERIFY(panel->error().isEmpty());
    // The cut list follows.
    action(w.get(), "action.cutList")->trigger();
    auto* cut = w->findChild<CutListDialog*>("cutListDialog");
    QVERIFY(cut);
    QTRY_VERIFY_WITH_TIMEOUT(cut->ready(), 30000);
    QCOMPARE(cut->rows().size(), std::size_t(1));
    QVERIFY(std::abs(cut->rows()[0].thickness - 19.05) <= cut->rows()[0].uncertainty + 1e-6);
    cut->close();

    // One undo step brings 18 mm back everywhere.
    w->session()->undoStack()->undo();
    QCOMPARE(panelThickness(), 18.0);
    QCOMPARE(table->item(0, ParametersPanel::ExpressionColumn)->text(), QString("18mm"));
    // Redo puts 3/4in back, in the table and the part; undo again for what follows.
    w->session()->undoStack()->redo();
    QCOMPARE(panelThickness(), 19.05);
    QCOMPARE(table->item(0, ParametersPanel::ExpressionColumn)->text(), QString("3/4in"));
    w->session()->undoStack()->undo();
    QCOMPARE(panelThickness(), 18.0);

    // A bad expression is refused under the table; nothing changes.
    table->item(0, ParametersPanel::ExpressionColumn)->setText("thickness + 1");
    QVERIFY2(panel->error().contains("refers back to itself"), qPrintable(panel->error()));
    QCOMPARE(table->item(0, ParametersPanel::ExpressionColumn)->text(), QString("18mm"));
    QCOMPARE(panelThickness(), 18.0);

    // Renamed: the expressions that use it follow; the part does not move.
    table->item(0, ParametersPanel::NameColumn)->setText("board");
    QCOMPARE(w->session()->document().root.find("panel")->expressions.at("size[0]"), std::string("board"));
    QCOMPARE(panelThickness(), 18.0);

    // In use: Delete is refused, saying where; a new unused one goes.
    table->setCurrentCell(0, ParametersPanel::NameColumn);
    panel->removeSelected();
    // Named as the panels name things, not "panel.size[0]".
    QVERIFY2(panel->error().startsWith("board is used by Size X of "), qPrintable(panel->error()));
    QVERIFY2(!panel->error().contains("size[0]"), qPrintable(panel->error()));
    // Any change to the document makes the refusal stale: it goes.
    w->session()->apply("touch", [](Document& d) { d.root.name = "Touched"; });
    QVERIFY(panel->error().isEmpty());
    w->session()->undoStack()->undo();
    table->setCurrentCell(0, ParametersPanel::NameColumn);
    panel->removeSelected();
    QVERIFY(!panel->error().isEmpty());
    QCOMPARE(table->rowCount(), 6);
    // Esc in the table takes the refusal's message away (it stayed, stale,
    // under the table).
    table->setFocus();
    QTest::keyClick(table, Qt::Key_Escape);
    QVERIFY2(panel->error().isEmpty(), qPrintable(panel->error()));
    QCOMPARE(table->rowCount(), 6);
    panel->addParameter();
    QCOMPARE(table->rowCount(), 7);
    QCOMPARE(table->item(6, ParametersPanel::NameColumn)->text(), QString("p"));
    if (auto* open = table->findChild<QLineEdit*>()) QTest::keyClick(open, Qt::Key_Escape);
    table->setCurrentCell(6, ParametersPanel::NameColumn);
    panel->removeSelected();
    QCOMPARE(table->rowCount(), 6);
    QVERIFY(panel->error().isEmpty());
    saveScreenshot(*w, "parameters-panel");

    // The property editor shows a driven field's value and keeps its expression;
    // a number typed over it replaces the expression (and only that one).
    w->selectNodes({"panel"});
    PropertyEditor* props = w->propertyEditor();
    QCOMPARE(props->expressionFor("size.x"), QString("board"));
    auto* sizeX = props->findChild<QuantityEdit*>("field.size.x");
    QVERIFY(sizeX);
    QCOMPARE(sizeX->value(), 18.0);
    QVERIFY(sizeX->toolTip().contains("= board"));
    QVERIFY(sizeX->property("driven").toBool());
    saveScreenshot(*w, "parameters-driven-field");
    sizeX->setValue(20.0);
    QTRY_COMPARE(panelThickness(), 20.0);
    QCOMPARE(props->expressionFor("size.x"), QString());
    QCOMPARE(props->expressionFor("size.z"), QString("height"));
    QVERIFY(!props->findChild<QuantityEdit*>("field.size.x")->property("driven").toBool());
    // Inches and fractions of an inch in any length field; the document stays in millimetres.
    typeInto(field(*w, "size.y"), "11 3/4in");
    QCOMPARE(w->session()->document().root.find("panel")->as<BoxParams>().size.y, 298.45);
    // The number kept is the decimal the inches are, bit for bit (2 3/8in
    // was saved as 60.324999999999996, QCOMPARE's fuzz hides it).
    typeInto(field(*w, "size.y"), "2 3/8in");
    QVERIFY(w->session()->document().root.find("panel")->as<BoxParams>().size.y == 60.325);
    typeInto(field(*w, "size.y"), "11 3/4in");
    QCOMPARE(props->errorFor("size.y"), QString());
    typeInto(field(*w, "rotate.z"), "2mm");
    QVERIFY2(props->errorFor("rotate.z").contains("a length does not belong here"), qPrintable(props->errorFor("rotate.z")));

    // "=" starts an expression in any field: it drives the field from then on.
    typeInto(field(*w, "size.y"), "=depth - 2mm");
    QCOMPARE(w->session()->document().root.find("panel")->as<BoxParams>().size.y, 298.0);
    QCOMPARE(props->expressionFor("size.y"), QString("depth - 2mm"));
    QCOMPARE(props->errorFor("size.y"), QString());
    QCOMPARE(field(*w, "size.y")->value(), 298.0);
    // Focused, a driven field shows its expression to edit.
    QuantityEdit* sizeY = field(*w, "size.y");
    QFocusEvent focusIn(QEvent::FocusIn, Qt::TabFocusReason); // (the test window need not be the active one)
    QApplication::sendEvent(sizeY, &focusIn);
    QVERIFY2(sizeY->findChild<QLineEdit*>()->text().startsWith("=depth - 2mm"), // (the field's unit follows)
             qPrintable(sizeY->findChild<QLineEdit*>()->text()));
    // One that does not evaluate is refused under the field, its text kept to mend.
    const Document before = w->session()->document();
    typeInto(field(*w, "size.z"), "=hieght");
    QVERIFY2(props->errorFor("size.z").contains("unknown name 'hieght': did you mean 'height'?"),
             qPrintable(props->errorFor("size.z")));
    QVERIFY(field(*w, "size.z")->findChild<QLineEdit*>()->text().startsWith("=hieght")); // (the unit may follow)
    QVERIFY(w->session()->document() == before);

    // In the panel, names complete as an expression is typed: the word under the cursor.
    table->setCurrentCell(2, ParametersPanel::ExpressionColumn);
    table->editItem(table->item(2, ParametersPanel::ExpressionColumn));
    QLineEdit* line = nullptr; // the editor just opened (an earlier one may not be deleted yet)
    for (QLineEdit* e : table->findChildren<QLineEdit*>())
        if (e->isVisible() && e->findChild<QCompleter*>("nameCompleter")) line = e;
    QVERIFY(line);
    line->selectAll();
    QTest::keyClicks(line, "2 * dep");
    auto* completer = line->findChild<QCompleter*>("nameCompleter");
    QVERIFY(completer);
    QCOMPARE(completer->currentCompletion(), QString("depth"));
    QVERIFY(completer->popup()->isVisible());
    QTest::keyClick(completer->popup(), Qt::Key_Return); // picks the name, commits nothing
    QCOMPARE(line->text(), QString("2 * depth"));
    QVERIFY(!completer->popup()->isVisible());
    QCOMPARE(w->session()->document().parameters[2].value, 1800.0);
    QTest::keyClick(line, Qt::Key_Return);
    QTRY_COMPARE(w->session()->document().parameters[2].value, 600.0);

    // And in a property field after '=': the Return that picks the name leaves
    // the typed text as it is (a spin box would put its number back), the next commits.
    QuantityEdit* sizeX2 = field(*w, "size.x");
    QApplication::sendEvent(sizeX2, &focusIn);
    sizeX2->selectAll();
    QTest::keyClicks(sizeX2, "=boa");
    // No unit after an expression being typed (it read "=apron_h - 20 mm").
    QCOMPARE(sizeX2->findChild<QLineEdit*>()->text(), QString("=boa"));
    auto* fieldCompleter = sizeX2->findChild<QCompleter*>("nameCompleter");
    QVERIFY(fieldCompleter);
    QVERIFY(fieldCompleter->popup()->isVisible());
    QCOMPARE(fieldCompleter->currentCompletion(), QString("board"));
    QTest::keyClick(fieldCompleter->popup(), Qt::Key_Return);
    QVERIFY2(sizeX2->findChild<QLineEdit*>()->text().startsWith("=board"), qPrintable(sizeX2->findChild<QLineEdit*>()->text()));
    QCOMPARE(props->expressionFor("size.x"), QString()); // not yet committed
    QTest::keyClicks(sizeX2, " + 1");
    QTest::keyClick(sizeX2, Qt::Key_Return);
    QCOMPARE(props->expressionFor("size.x"), QString("board + 1"));
    QCOMPARE(panelThickness(), 19.0);
    QCOMPARE(props->errorFor("size.x"), QString());
    // The completer's list closing gives the field its focus back (as a
    // popup's focus): what is being typed stays. A newcomer's "=thic" became
    // the document's expression, selected, and the next key replaced it.
    sizeX2->selectAll();
    QTest::keyClicks(sizeX2, "=boa");
    QFocusEvent fromPopup(QEvent::FocusIn, Qt::PopupFocusReason);
    QApplication::sendEvent(sizeX2, &fromPopup);
    QCOMPARE(sizeX2->findChild<QLineEdit*>()->text(), QString("=boa"));
    QTest::keyClicks(sizeX2, "rd + 2");
    QTest::keyClick(sizeX2, Qt::Key_Return);
    QCOMPARE(props->expressionFor("size.x"), QString("board + 2"));
    QCOMPARE(panelThickness(), 20.0);
    // A number is not a name: "=18" offers nothing.
    sizeX2->selectAll();
    QTest::keyClicks(sizeX2, "=18");
    QVERIFY(!fieldCompleter->popup()->isVisible());
    QTest::keyClick(sizeX2, Qt::Key_Escape);
    // Other features' numbers complete too, ids with '-' whole: a newcomer
    // could not refer to a board's size without knowing its id, which the
    // application shows nowhere else. Subtraction still completes the name after '-'.
    sizeX2->selectAll();
    QTest::keyClicks(sizeX2, "=dado-b");
    QVERIFY(fieldCompleter->popup()->isVisible());
    QCOMPARE(fieldCompleter->currentCompletion(), QString("dado-bottom.size[0]"));
    QTest::keyClicks(sizeX2, "ottom.size[2");
    QCOMPARE(fieldCompleter->currentCompletion(), QString("dado-bottom.size[2]"));
    QTest::keyClick(fieldCompleter->popup(), Qt::Key_Return);
    QVERIFY2(sizeX2->findChild<QLineEdit*>()->text().startsWith("=dado-bottom.size[2]"),
             qPrintable(sizeX2->findChild<QLineEdit*>()->text()));
    sizeX2->selectAll();
    QTest::keyClicks(sizeX2, "=depth-boa");
    QVERIFY(fieldCompleter->popup()->isVisible());
    QCOMPARE(fieldCompleter->currentCompletion(), QString("board"));
    QTest::keyClick(fieldCompleter->popup(), Qt::Key_Escape); // the popup, then the typing
    QVERIFY(!fieldCompleter->popup()->isVisible());
    QTest::keyClick(sizeX2, Qt::Key_Escape);

    // A parameter's name typed without the '=' is the same expression (a
    // newcomer typed "top_t/2" and was told it was no number); a word that
    // names nothing is still no number, and says so.
    // (The window active, as a person's is: the field entered keeps the focus.)
    w->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(w.get()));
    typeInto(field(*w, "size.x"), "board + 3");
    QVERIFY(field(*w, "size.x")->hasFocus());
    QCOMPARE(props->expressionFor("size.x"), QString("board + 3"));
    QCOMPARE(panelThickness(), 21.0);
    // The field entered holds the new value (shown when the focus leaves it).
    QCOMPARE(field(*w, "size.x")->value(), 21.0);
    QCOMPARE(props->errorFor("size.x"), QString());
    typeInto(field(*w, "size.x"), "boards");
    QVERIFY2(props->errorFor("size.x").contains("cannot read 'boards'"), qPrintable(props->errorFor("size.x")));
    // Another feature's value without the '=': said how to write it.
    typeInto(field(*w, "size.x"), "frob.size[0] + 20");
    QVERIFY2(props->errorFor("size.x").contains("start with '=': =frob.size[0]"), qPrintable(props->errorFor("size.x")));
    QCOMPARE(props->expressionFor("size.x"), QString("board + 3"));
    typeInto(field(*w, "size.x"), "19mm");
    QCOMPARE(props->expressionFor("size.x"), QString());
    QCOMPARE(panelThickness(), 19.0);
}

// View > Lengths In > Inches and Fractions: every length field, readout and
// table speaks inches; numbers typed without a unit are inches; the
// document keeps millimetres, and an expression whose bare number would be
// millimetres is refused with the reason before it is stored.
void MainWindowTest::lengthsShownInInchesAreTypedInInchesAndTheDocumentKeepsMillimetres()
{
    auto w = makeWindow(recovery_.path());
    QVERIFY(w->openFile(std::filesystem::path(KERF_EXAMPLES_DIR) / "bookshelf-side-parametric.kerf"));
    auto panelSize = [&] { return w->session()->document().root.find("panel")->as<BoxParams>().size; };
    auto text = [&](const QString& key) { return field(*w, key)->findChild<QLineEdit*>()->text(); };
    action(w.get(), "action.lengths.mm")->trigger(); // (the choice is remembered: an earlier run may have left inches)
    w->selectNodes({"panel"});
    QCOMPARE(text("size.x"), QString("18 mm"));
    action(w.get(), "action.lengths.in")->trigger();
    QVERIFY(action(w.get(), "action.lengths.in")->isChecked());
    QVERIFY(!action(w.get(), "action.lengths.mm")->isChecked());
    QCOMPARE(text("size.x"), QString("0.708661\"")); // 18 mm is no whole 64th: exact decimals to edit
    auto* table = w->findChild<QTableWidget*>("parameters.table");
    QVERIFY(table);
    QCOMPARE(table->item(0, ParametersPanel::ValueColumn)->text(), QString("≈ 45/64\"")); // a readout says it rounds

    // The stock is 3/4 inch: the parameter, the driven field and the table agree.
    table->item(0, ParametersPanel::ExpressionColumn)->setText("3/4in");
    QCOMPARE(panelSize().x, 19.05);
    QTRY_COMPARE(text("size.x"), QString("3/4\"")); // (the editor refreshes once the part is resolved)
    QCOMPARE(table->item(0, ParametersPanel::ValueColumn)->text(), QString("3/4\""));

    // A mixed number without a unit is inches here; the document stores millimetres.
    typeInto(field(*w, "size.y"), "11 3/4");
    QCOMPARE(panelSize().y, 298.45);
    QCOMPARE(text("size.y"), QString("11 3/4\""));
    QCOMPARE(w->propertyEditor()->errorFor("size.y"), QString());
    typeInto(field(*w, "size.y"), "300mm"); // millimetres still read as such
    QCOMPARE(panelSize().y, 300.0);

    // "=height - 2" would subtract 2 mm: said, not stored.
    const Document before = w->session()->document();
    typeInto(field(*w, "size.z"), "=height - 2");
    QVERIFY2(w->propertyEditor()->errorFor("size.z").contains("a number without a unit is in millimetres"),
             qPrintable(w->propertyEditor()->errorFor("size.z")));
    QVERIFY(w->session()->document() == before);
    typeInto(field(*w, "size.z"), "=height - 2in");
    QCOMPARE(panelSize().z, 1800.0 - 50.8);
    QCOMPARE(w->propertyEditor()->expressionFor("size.z"), QString("height - 2in"));
    QCOMPARE(w->propertyEditor()->errorFor("size.z"), QString());

    // Readouts: the bounding box and the cut list in inches and 64ths.
    w->selectNodes({});
    action(w.get(), "action.boundingBox")->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(w->measureText().startsWith("Bounding box: 3/4\" x ≈ 11 13/16\" x ≈ 68 55/64\""), 30000);
    action(w.get(), "action.cutList")->trigger();
    auto* cut = w->findChild<CutListDialog*>("cutListDialog");
    QVERIFY(cut);
    QTRY_VERIFY_WITH_TIMEOUT(cut->ready(), 30000);
    auto* cutTable = cut->findChild<QTableWidget*>("cutlist.table");
    QCOMPARE(cutTable->horizontalHeaderItem(4)->text(), QString("Thickness (in)"));
    QCOMPARE(cutTable->item(0, 4)->text(), QString("3/4\""));
    saveScreenshot(*w, "app-lengths-in-inches");
    cut->close();

    // Back to millimetres: the same document, shown as before.
    action(w.get(), "action.lengths.mm")->trigger();
    w->selectNodes({"panel"});
    QCOMPARE(text("size.x"), QString("19.05 mm"));
    QCOMPARE(table->item(0, ParametersPanel::ValueColumn)->text(), QString("19.05 mm"));
}

QTEST_MAIN(MainWindowTest)
#include "MainWindowTest.moc"

// A revolve (the turned leg's primitive) from the Add menu: its profile is a
// table of [r, z] points; an edit goes in as one undo step, an r below the
// axis is refused under the table, and the view shows the turning.
void MainWindowTest::aTurnedProfileIsEditedInItsPointTable()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    action(w.get(), "action.add.revolve")->trigger();
    QCOMPARE(w->selectedNodeIds(), std::vector<std::string>{"revolve"});
    auto* table = w->propertyEditor()->findChild<QTableWidget*>("field.profile");
    QVERIFY(table);
    QCOMPARE(table->horizontalHeaderItem(0)->text(), QString("R (mm)"));
    QCOMPARE(table->horizontalHeaderItem(1)->text(), QString("Z (mm)"));
    const auto profile = [&] { return w->session()->document().root.find("revolve")->as<RevolveParams>().profile; };
    QCOMPARE(table->rowCount(), int(profile().size()));
    QCOMPARE(table->item(1, 0)->text(), QString::number(profile()[1].x));

    // The foot wider: one step, the document and the table agree.
    const int steps = w->session()->undoStack()->count();
    table->item(1, 0)->setText("15");
    QCOMPARE(profile()[1].x, 15.0);
    QCOMPARE(w->session()->undoStack()->count(), steps + 1);
    QCOMPARE(w->propertyEditor()->errorFor("profile"), QString());

    // A point across the axis: refused with the point named, nothing changes.
    const Document before = w->session()->document();
    table->item(2, 0)->setText("-3");
    QVERIFY(w->session()->document() == before);
    const QString why = w->propertyEditor()->errorFor("profile");
    // The point as its table row numbers it (the file's key is profile[2][0]).
    QVERIFY2(why.startsWith("Profile, point 3 of the revolve: r must be >= 0"), qPrintable(why));
    QVERIFY2(why.endsWith("(not applied: the part keeps its last profile)"), qPrintable(why));
    // What was typed stays to be mended: an outline typed point by point
    // crosses itself until a point's second coordinate is in, and a newcomer
    // lost each first one.
    QCOMPARE(table->item(2, 0)->text(), QString("-3"));
    table->item(2, 0)->setText(QString::number(profile()[2].x));
    QVERIFY(w->session()->document() == before);
    QCOMPARE(w->propertyEditor()->errorFor("profile"), QString());

    // Undo takes the wider foot back, and a refusal about the profile as it
    // was with it (a newcomer's "point 4: not a number" stayed after Undo).
    table->item(2, 0)->setText("abc");
    QVERIFY2(w->propertyEditor()->errorFor("profile").startsWith("point 3: not a number"),
             qPrintable(w->propertyEditor()->errorFor("profile")));
    action(w.get(), "action.undo")->trigger();
    QCOMPARE(profile()[1].x, 12.0);
    QCOMPARE(table->item(1, 0)->text(), QString("12"));
    QCOMPARE(table->item(2, 0)->text(), QString::number(profile()[2].x));
    QCOMPARE(w->propertyEditor()->errorFor("profile"), QString());

    // The view shows the turning, with no validation error.
    w->selectNodes({});
    action(w.get(), "action.view.front")->trigger();
    action(w.get(), "action.fitAll")->trigger();
    QVERIFY(waitForViewport(*w));
    const QImage frame = w->viewport()->grabFrame();
    QVERIFY(!frame.isNull());
    QVERIFY2(woodFraction(frame) > 0.02, "the turning fills part of the picture");
    QVERIFY2(w->viewport()->status().validationErrors == 0, qPrintable(w->viewport()->status().lastValidationMessage));
    saveScreenshot(*w, "app-revolve-profile");
}

// A profile point driven by a parameter (a newcomer's curved rail: "=-length/2"
// in a point's cell was "point 1: not a number", so the board never followed
// the length, its tenons did). Typed with '=', the coordinate is the
// expression's: shown tinted with it in the tooltip, following the
// parameter, kept when another point goes in before it, replaced by a number
// typed over it. Add point walks on along the outline.
void MainWindowTest::aProfilePointFollowsAParameter()
{
    auto w = makeWindow(recovery_.path());
    action(w.get(), "action.new")->trigger();
    QVERIFY(w->session()->apply("Add length", [](Document& d) {
        d.parameters.push_back(Parameter{.name = "length", .expression = "400", .comment = {}, .unit = "length"});
    }));
    action(w.get(), "action.add.extrude")->trigger();
    const std::string id = w->selectedNodeIds().front();
    auto* table = w->propertyEditor()->findChild<QTableWidget*>("field.profile");
    QVERIFY(table);
    const auto node = [&] { return w->session()->document().root.find(id); };
    const auto points = [&] { return node()->as<ExtrudeParams>().profile; };
    const int rows = table->rowCount();
    QVERIFY(rows >= 3);

    table->item(0, 0)->setText("=-length/2");
    QCOMPARE(w->propertyEditor()->errorFor("profile"), QString());
    QCOMPARE(points()[0].x, -200.0);
    QCOMPARE(node()->expressions.at("profile[0][0]"), std::string("-length/2"));
    QCOMPARE(table->item(0, 0)->text(), QString("-200"));
    QVERIFY(table->item(0, 0)->toolTip().startsWith("= -length/2"));

    // The parameter changed: the point follows.
    QVERIFY(w->session()->apply("Longer", [](Document& d) { d.parameters[0].expression = "500"; }));
    QCOMPARE(points()[0].x, -250.0);

    // A point added after the first: each expression stays with its point,
    // the second point's now the third's.
    table->item(1, 1)->setText("=-length/50");
    QCOMPARE(points()[1].y, -10.0);
    table->setCurrentCell(0, 0);
    auto* add = w->propertyEditor()->findChild<QPushButton*>("profile.add");
    QVERIFY(add);
    QTest::mouseClick(add, Qt::LeftButton);
    QCOMPARE(int(points().size()), rows + 1);
    QCOMPARE(node()->expressions.at("profile[0][0]"), std::string("-length/2"));
    QCOMPARE(node()->expressions.at("profile[2][1]"), std::string("-length/50"));
    QVERIFY(!node()->expressions.count("profile[1][1]"));
    // Pressed again, the next point goes after the new one, not between the
    // first two again.
    const glm::dvec2 added = points()[1];
    QTest::mouseClick(add, Qt::LeftButton);
    QCOMPARE(points()[1], added);

    // A number typed over it replaces the expression (further out: the
    // points added lie on the edge between it and the next corner).
    table->item(0, 0)->setText("-300");
    QCOMPARE(w->propertyEditor()->errorFor("profile"), QString());
    QCOMPARE(points()[0].x, -300.0);
    QVERIFY(!node()->expressions.count("profile[0][0]"));
    QVERIFY(w->session()->apply("Longer again", [](Document& d) { d.parameters[0].expression = "600"; }));
    QCOMPARE(points()[0].x, -300.0);
}

// View > Voxelize on the GPU (issue 18): the GPU voxelizer in the viewport's
// background builds the part (its preview, then full depth) and every edit
// (straight to full depth, the last build on screen meanwhile), the CPU
// voxelizer is not asked; back on the CPU the picture is the same; a part
// beyond the voxel memory budget is refused in words and the CPU takes over.
void MainWindowTest::theGpuVoxelizesWhenAskedAndTheCpuTakesOverWhenItCannot()
{
    // A small drilled board: lavapipe builds it in seconds.
    const QString doc = files_.path() + "/gpu-board.kerf";
    {
        QFile f(doc);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write(R"({"format":"kerf","version":1,"settings":{"feature_size":0.5},
            "root":{"id":"d","type":"difference","children":[
            {"id":"board","type":"box","size":[80,50,18]},
            {"id":"hole","type":"cylinder","radius":6,"height":40,"transform":{"translate":[15,0,0]}}]}})");
    }
    MainWindowOptions options;
    options.voxelizeOnGpu = true;
    auto w = makeWindow(recovery_.path(), options);
    if (!w->viewport()->canVoxelizeOnGpu()) QSKIP("the viewport has no Vulkan device");
    QAction* onGpu = action(w.get(), "action.voxelizeOnGpu");
    QVERIFY(onGpu->isEnabled());
    QVERIFY(onGpu->isChecked());
    const std::uint64_t cpuRequests = w->voxelizer()->lastSubmitted();
    QVERIFY(w->openFile(doc.toStdString()));
    QVERIFY(w->voxelizingOnGpu());
    QVERIFY(waitForGpuVoxels(*w, 0));
    const QImage board = w->viewport()->grabFrame();
    QVERIFY2(woodFraction(board) > 0.03, "the board fills part of the picture");
    QTRY_VERIFY(w->findChild<QLabel*>("status.voxels")->text().startsWith("Voxels (GPU)"));
    saveScreenshot(*w, "app-gpu-voxels");

    // An edit: built on the GPU, the picture changes; the CPU voxelizer is never asked.
    const std::uint64_t shown = w->viewport()->status().shownVersion;
    w->selectNodes({"hole"});
    QuantityEdit* radius = field(*w, "radius");
    typeInto(radius, "14");
    QVERIFY(waitForGpuVoxels(*w, shown));
    const QImage edited = w->viewport()->grabFrame();
    QVERIFY2(pictureDifference(board, edited) > 0.002, "the picture shows the wider hole");
    QCOMPARE(w->voxelizer()->lastSubmitted(), cpuRequests);

    // Back on the CPU: its voxels of the same document make the same picture.
    onGpu->trigger();
    QVERIFY(!w->voxelizingOnGpu());
    QVERIFY(waitForViewport(*w));
    QTRY_VERIFY_WITH_TIMEOUT(!w->viewport()->status().gpuVoxels, kVoxelTimeoutMs);
    const QImage onTheCpu = w->viewport()->grabFrame();
    QVERIFY2(pictureDifference(edited, onTheCpu) < 0.005, "the GPU's and the CPU's voxels look the same");

    // A voxel budget the GPU's pools cannot keep to: said, and the CPU voxelizes.
    qputenv("KERF_GPU_BUDGET_MB", "1");
    onGpu->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(w->lastMessage().contains("The GPU cannot voxelize this part"), kVoxelTimeoutMs);
    qunsetenv("KERF_GPU_BUDGET_MB");
    QVERIFY2(w->lastMessage().contains("MB"), qPrintable(w->lastMessage()));
    QVERIFY(!onGpu->isChecked());
    QVERIFY(!w->voxelizingOnGpu());
    QVERIFY(w->voxelizer()->lastSubmitted() > cpuRequests);
    QVERIFY(waitForViewport(*w));
    QVERIFY(woodFraction(w->viewport()->grabFrame()) > 0.03);
    const auto status = w->viewport()->status();
    QVERIFY2(status.validationErrors == 0, qPrintable(status.lastValidationMessage));
}
