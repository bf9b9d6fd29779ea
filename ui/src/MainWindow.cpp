#include "MainWindow.hpp"

#include "FeatureTreeModel.hpp"
#include "MeasureTool.hpp"
#include "MoveTool.hpp"
#include "ParametersPanel.hpp"
#include "PropertyEditor.hpp"
#include "SectionPanel.hpp"
#include "SelectionGhosts.hpp"
#include "StatusReadout.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/DirtyRegion.hpp"
#include "kerf/viewport/ReferenceMesh.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QDockWidget>
#include <QHeaderView>
#include <QLabel>
#include <QMenu>
#include <QScrollArea>
#include <QSignalBlocker>
#include <QSettings>
#include <QStatusBar>
#include <QTimer>
#include <QTreeView>

#include <glm/glm.hpp>

namespace kerf::ui {

namespace fs = std::filesystem;

MainWindow::MainWindow(MainWindowOptions options) : options_(std::move(options))
{
    setObjectName("mainWindow");
    setAcceptDrops(true);
    session_ = new DocumentSession(this);
    {
        VoxelizerOptions vo;
        vo.memoryBudgetBytes = memoryBudgetBytes();
        voxelizer_ = new VoxelizerBridge(this, vo);
    }
    recovery_ = std::make_unique<RecoveryStore>(options_.recoveryFolder);
    model_ = new FeatureTreeModel(session_, this);

    viewport_ = new qt::ViewportWidget(this);
    viewport_->setObjectName("viewport");
    setCentralWidget(viewport_);

    tree_ = new QTreeView(this);
    tree_->setObjectName("featureTree");
    tree_->setModel(model_);
    tree_->setSelectionMode(QAbstractItemView::ExtendedSelection);
    tree_->setDragDropMode(QAbstractItemView::InternalMove);
    tree_->setDefaultDropAction(Qt::MoveAction);
    tree_->setDragEnabled(true);
    tree_->setAcceptDrops(true);
    tree_->setDropIndicatorShown(true);
    // Rename with F2 or Edit > Rename only: a click on the selected row
    // (to leave a field, say) must not open an editor that swallows Ctrl+Z.
    tree_->setEditTriggers(QAbstractItemView::EditKeyPressed);
    tree_->setContextMenuPolicy(Qt::CustomContextMenu);
    tree_->header()->setSectionResizeMode(0, QHeaderView::Stretch);
    tree_->header()->setSectionResizeMode(1, QHeaderView::ResizeToContents);
    tree_->header()->setStretchLastSection(false);
    tree_->setMinimumWidth(300);
    tree_->expandAll();

    properties_ = new PropertyEditor(session_, this);
    properties_->setObjectName("propertyEditor");

    buildActions();
    buildDocks();
    buildStatusBar();
    restoreLayout();

    measure_ = new MeasureTool(session_, viewport_, measureLabel_, this);
    connect(measure_, &MeasureTool::message, this, [this](const QString& m) { showMessage(m); });
    move_ = new MoveTool(session_, viewport_, this);
    connect(move_, &MoveTool::message, this, [this](const QString& m) {
        if (m.isEmpty()) statusBar()->clearMessage();
        else showMessage(m, 0);
    });
    ghosts_ = new SelectionGhosts(viewport_, this);

    connect(session_, &DocumentSession::documentChanged, this, &MainWindow::onDocumentChanged);
    connect(session_, &DocumentSession::stateChanged, this, &MainWindow::updateTitle);
    connect(model_, &QAbstractItemModel::modelAboutToBeReset, this, [this] {
        expanded_.clear();
        inTreeBeforeReset_.clear();
        // Remember which rows are open and selected, by node id.
        std::function<void(const QModelIndex&)> walk = [&](const QModelIndex& parent) {
            for (int r = 0; r < model_->rowCount(parent); ++r) {
                const QModelIndex i = model_->index(r, 0, parent);
                inTreeBeforeReset_.insert(model_->nodeIdAt(i));
                if (tree_->isExpanded(i)) expanded_.push_back(model_->nodeIdAt(i));
                walk(i);
            }
        };
        walk({});
        selectionBeforeReset_ = selectedNodeIds();
        resettingTree_ = true; // the selection the view clears now is not the person's
    });
    connect(model_, &QAbstractItemModel::modelReset, this, [this] {
        resettingTree_ = false;
        for (const auto& id : expanded_) tree_->setExpanded(model_->indexOf(id), true);
        tree_->setExpanded(model_->index(0, 0), true);
        // A feature new to the tree opens, with what it holds in sight: a
        // deletion undone came back closed, a mirror just made hid the part
        // it mirrors. (Opening a file closes the tree to its first level.)
        std::function<void(const QModelIndex&)> openNew = [&](const QModelIndex& parent) {
            for (int r = 0; r < model_->rowCount(parent); ++r) {
                const QModelIndex i = model_->index(r, 0, parent);
                if (!inTreeBeforeReset_.contains(model_->nodeIdAt(i))) tree_->setExpanded(i, true);
                openNew(i);
            }
        };
        if (!inTreeBeforeReset_.empty()) openNew({});
        std::vector<std::string> keep;
        for (const auto& id : selectionBeforeReset_)
            if (session_->document().root.find(id)) keep.push_back(id);
        selectNodes(keep);
    });
    connect(tree_->selectionModel(), &QItemSelectionModel::selectionChanged, this, &MainWindow::onSelectionChanged);
    connect(model_, &FeatureTreeModel::editRefused, this, [this](const QString& why) { showMessage(why); });
    model_->setConfirm([this](const QString& question) {
        if (options_.askConfirm) return options_.askConfirm(question);
        return QMessageBox::question(this, tr("Reorder"), question, QMessageBox::Yes | QMessageBox::Cancel,
                                     QMessageBox::Cancel) == QMessageBox::Yes;
    });
    connect(viewport_, &qt::ViewportWidget::clicked, this, &MainWindow::onViewportClicked);
    connect(viewport_, &qt::ViewportWidget::frameDrawn, this, &MainWindow::updateStatus);
    connect(viewport_, &qt::ViewportWidget::backendChanged, this, [this] {
        showMessage(tr("The viewport uses the CPU reference tracer: %1").arg(viewport_->status().fallbackReason), 0);
        // Vulkan gone: the GPU voxelizer with it; the CPU voxelizer takes the document.
        voxelizeOnGpu_->setEnabled(false);
        if (gpuLayout_) voxelizeAgain();
    });
    // The view's needs go to the CPU voxelizer; the GPU builds the whole part at full depth.
    connect(viewport_, &qt::ViewportWidget::viewSettled, this, [this](const ViewRequirement& v) {
        if (refineForView_->isChecked() && !voxelizingOnGpu()) voxelizer_->setView(v);
    });
    connect(viewport_, &qt::ViewportWidget::pictureTaken, this, [this](std::shared_ptr<const OcclusionMap> picture) {
        if (refineForView_->isChecked() && !voxelizingOnGpu()) voxelizer_->setOcclusion(std::move(picture));
    });
    connect(viewport_, &qt::ViewportWidget::gpuVoxelizerRefused, this, [this](const QString& reason) {
        // Not saved: the next part (or the menu) may try the GPU again.
        const QSignalBlocker quiet(voxelizeOnGpu_);
        voxelizeOnGpu_->setChecked(false);
        showMessage(tr("The GPU cannot voxelize this part (%1): the CPU voxelizes it").arg(reason), 15000);
        voxelizeAgain();
    });
    connect(voxelizer_, &VoxelizerBridge::published, this, [this](std::shared_ptr<const VoxelSnapshot> s) {
        sayWhenNothingShows(*s);
        viewport_->setSnapshot(std::move(s));
        updateStatus();
    });

    autosave_ = new QTimer(this);
    autosave_->setInterval(options_.autosaveMs);
    connect(autosave_, &QTimer::timeout, this, &MainWindow::autosaveNow);
    autosave_->start();
    progressTimer_ = new QTimer(this);
    progressTimer_->setInterval(100);
    connect(progressTimer_, &QTimer::timeout, this, &MainWindow::updateStatus);
    progressTimer_->start();

    resize(1400, 860);
    onDocumentChanged();
    updateTitle();
    if (!viewport_->status().vulkan)
        showMessage(tr("No usable Vulkan device (%1): the viewport uses the CPU reference tracer.")
                        .arg(viewport_->status().fallbackReason),
                    0);
}

MainWindow::~MainWindow()
{
    // The children go after this body, the session among them (its undo
    // stack signals as it dies): none may call back into a window that is
    // no longer one.
    for (QObject* child : std::initializer_list<QObject*>{session_, voxelizer_, model_, viewport_, properties_})
        child->disconnect(this);
    autosave_->stop();
    progressTimer_->stop();
}

std::size_t MainWindow::memoryBudgetBytes() const
{
    // KERF_GPU_BUDGET_MB (tests, scripts), else the setting, else 1 GiB: a
    // fraction of any GPU Kerf runs on, and a scene far beyond what a screen shows.
    const QString env = qEnvironmentVariable("KERF_GPU_BUDGET_MB");
    const qlonglong mb = !env.isEmpty() ? env.toLongLong() : QSettings().value("voxelBudgetMB", 1024).toLongLong();
    return std::size_t(std::max<qlonglong>(mb, 1)) << 20;
}

void MainWindow::buildDocks()
{
    auto* treeDock = new QDockWidget(tr("Features"), this);
    treeDock->setObjectName("dock.features");
    treeDock->setWidget(tree_);
    addDockWidget(Qt::LeftDockWidgetArea, treeDock);

    // The document's named parameters, under the tree: what the features are designed in.
    auto* parameters = new ParametersPanel(session_, this);
    parameters->setObjectName("parametersPanel");
    auto* parametersDock = new QDockWidget(tr("Parameters"), this);
    parametersDock->setObjectName("dock.parameters");
    parametersDock->setWidget(parameters);
    addDockWidget(Qt::LeftDockWidgetArea, parametersDock);
    splitDockWidget(treeDock, parametersDock, Qt::Vertical);

    auto* scroll = new QScrollArea(this);
    scroll->setWidget(properties_);
    scroll->setWidgetResizable(true);
    auto* propDock = new QDockWidget(tr("Properties"), this);
    propDock->setObjectName("dock.properties");
    propDock->setWidget(scroll);
    addDockWidget(Qt::RightDockWidgetArea, propDock);

    // Section view: a clipping plane across X, Y or Z at a draggable offset.
    auto* section = new SectionPanel(
        [this] {
            if (gpuLayout_ && gpuLayout_->tileCount() > 0) return gpuLayout_->bounds();
            const Aabb part = voxelizer_->latest() ? voxelizer_->latest()->layout.bounds() : Aabb::empty();
            return part.isEmpty() ? Aabb{glm::dvec3(-100), glm::dvec3(100)} : part; // nothing yet: round the origin
        },
        [this] { return viewport_->camera().eye(); }, this);
    connect(section, &SectionPanel::sectionChanged, viewport_, &qt::ViewportWidget::setSection);
    auto* sectionDock = new QDockWidget(tr("Section"), this);
    sectionDock->setObjectName("dock.section");
    sectionDock->setWidget(section);
    addDockWidget(Qt::RightDockWidgetArea, sectionDock);

    measureLabel_ = new QLabel(this);
    measureLabel_->setObjectName("measure.result");
    measureLabel_->setWordWrap(true);
    measureLabel_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    measureLabel_->setMargin(6);
    measureLabel_->setAlignment(Qt::AlignTop | Qt::AlignLeft);
    auto* measureDock = new QDockWidget(tr("Measure"), this);
    measureDock->setObjectName("dock.measure");
    measureDock->setWidget(measureLabel_);
    addDockWidget(Qt::RightDockWidgetArea, measureDock);
    // Section and measure share a tabbed area under the properties.
    tabifyDockWidget(sectionDock, measureDock);
    sectionDock->raise();
    propDock->setMinimumWidth(350);
    // The properties take most of the right side: a box's size and position
    // are twelve rows, the section's controls four.
    resizeDocks({propDock, sectionDock}, {560, 180}, Qt::Vertical);

    // The docks' toggles go in the View menu.
    for (QDockWidget* d : {treeDock, parametersDock, propDock, sectionDock, measureDock})
        commands_.view->addAction(d->toggleViewAction());
}

void MainWindow::buildStatusBar() { status_ = new StatusReadout(statusBar()); }

// ---------------------------------------------------------------------------
// Document and selection

void MainWindow::onDocumentChanged()
{
    if (!messageUntilEdit_.isEmpty()) {
        if (statusBar()->currentMessage() == messageUntilEdit_) statusBar()->clearMessage();
        messageUntilEdit_.clear();
    }
    const Document& doc = session_->document();
    std::shared_ptr<const Tape> tape;
    try {
        tape = std::make_shared<const Tape>(compileTape(doc));
        viewport_->setPickTape(tape);
    } catch (const std::exception& e) {
        showMessage(tr("The part could not be compiled: %1").arg(QString::fromUtf8(e.what())));
    }
    voxelize(doc, std::move(tape));
    if (doc.meshes != loadedMeshes_) {
        std::vector<std::string> problems;
        const fs::path folder = session_->path() ? session_->path()->parent_path() : fs::current_path();
        viewport_->setMeshes(loadReferenceMeshes(doc, folder, problems));
        for (const auto& p : problems) showMessage(QString::fromStdString(p) + tr(" (left out)"), 10000);
        loadedMeshes_ = doc.meshes;
    }
    onSelectionChanged();
    updateTitle();
}

std::vector<std::string> MainWindow::selectedNodeIds() const
{
    std::vector<std::string> ids;
    for (const QModelIndex& i : tree_->selectionModel()->selectedRows(0)) ids.push_back(model_->nodeIdAt(i));
    // In tree order, so that grouping keeps the order of the siblings.
    return edit::inTreeOrder(session_->document(), ids);
}

void MainWindow::selectNodes(const std::vector<std::string>& ids)
{
    QItemSelection selection;
    QModelIndex current;
    for (const auto& id : ids) {
        const QModelIndex i = model_->indexOf(id);
        if (!i.isValid()) continue;
        selection.select(i, model_->indexOf(id, FeatureTreeModel::TypeColumn));
        current = i;
        for (QModelIndex p = i.parent(); p.isValid(); p = p.parent()) tree_->setExpanded(p, true);
    }
    tree_->selectionModel()->select(selection, QItemSelectionModel::ClearAndSelect);
    if (current.isValid()) {
        tree_->selectionModel()->setCurrentIndex(current, QItemSelectionModel::NoUpdate);
        tree_->scrollTo(current);
    }
    onSelectionChanged();
}

void MainWindow::onSelectionChanged()
{
    if (resettingTree_) return;
    const std::vector<std::string> ids = selectedNodeIds();
    properties_->setSelection(ids);
    std::unordered_set<std::string> features;
    for (const auto& id : ids)
        if (const Node* n = session_->document().root.find(id)) features.merge(edit::primitiveIdsInSubtree(*n));
    viewport_->setSelectedFeatureNodes(std::move(features));
    move_->setNode(ids.size() == 1 ? ids.front() : std::string());
    ghosts_->show(session_->document(), ids);
}

void MainWindow::onViewportClicked(const qt::ViewportPick& pick)
{
    if (measureAction_->isChecked()) {
        measure_->click(pick);
        return;
    }
    if (!pick.hit || pick.nodeId.empty()) {
        if (!(pick.modifiers & Qt::ControlModifier)) selectNodes({});
        return;
    }
    std::vector<std::string> ids;
    if (pick.modifiers & Qt::ControlModifier) ids = selectedNodeIds();
    auto it = std::find(ids.begin(), ids.end(), pick.nodeId);
    if (it != ids.end()) ids.erase(it);
    else ids.push_back(pick.nodeId);
    selectNodes(ids);
}

QString MainWindow::measureText() const { return measureLabel_->text(); }

bool MainWindow::ghostsBusy() const { return ghosts_->busy(); }

// ---------------------------------------------------------------------------
// Title and status

void MainWindow::updateTitle()
{
    setWindowTitle(tr("%1[*] — Kerf").arg(session_->displayName()));
    setWindowModified(session_->isModified());
}

void MainWindow::showMessage(const QString& text, int timeoutMs)
{
    lastMessage_ = text;
    statusBar()->showMessage(text, timeoutMs);
}

void MainWindow::showMessageUntilEdit(const QString& text)
{
    showMessage(text, 0);
    messageUntilEdit_ = text;
}

bool MainWindow::voxelizingOnGpu() const
{
    return voxelizeOnGpu_ && voxelizeOnGpu_->isChecked() && viewport_->canVoxelizeOnGpu();
}

void MainWindow::voxelize(const Document& doc, std::shared_ptr<const Tape> tape)
{
    // The GPU builds the whole part at full depth: refining for the view is the CPU voxelizer's.
    refineForView_->setEnabled(!voxelizingOnGpu());
    if (voxelizingOnGpu() && tape) {
        const GridLayout layout = voxelizer_->voxelizer().layoutFor(doc, *tape);
        // An edit on the same grid rebuilds only the tiles it reaches.
        std::optional<std::vector<long>> dirty;
        if (gpuDocument_ && gpuLayout_ && *gpuLayout_ == layout) dirty = tilesAnEditReaches(*gpuDocument_, doc, layout);
        gpuLayout_ = layout;
        gpuDocument_ = doc;
        const std::uint64_t since = gpuRevision_;
        viewport_->setGpuVoxelSource(std::move(tape), layout, ++gpuRevision_, memoryBudgetBytes(), std::move(dirty),
                                     since);
        return;
    }
    gpuLayout_.reset();
    gpuDocument_.reset();
    viewport_->clearGpuVoxelSource(); // its last build stays on screen until the CPU's is there
    voxelizer_->submit(doc);
}

void MainWindow::voxelizeAgain()
{
    std::shared_ptr<const Tape> tape;
    try {
        tape = std::make_shared<const Tape>(compileTape(session_->document()));
    } catch (const std::exception&) {
        // Said when the document changed; the CPU voxelizer reports it too.
    }
    voxelize(session_->document(), std::move(tape));
}

void MainWindow::sayWhenNothingShows(const VoxelSnapshot& s)
{
    // A part whose every feature is thinner than a voxel voxelizes to
    // nothing: the view went blank without a word when a newcomer made an
    // array of 2000 legs (100 m long, so 100 mm voxels for 40 mm legs).
    // Or the part is empty: a box cut away by a box of its own size said
    // "every feature is thinner than a voxel" to a newcomer, who had cut it
    // all away. Which of the two, the voxels cannot tell; both are said.
    const QString nothing = tr("Nothing shows at the view feature size of %1 mm: the part is empty (cut away by "
                               "its tools), or every feature of it is thinner than a voxel (a finer View feature "
                               "size in Properties, with nothing selected, shows those).");
    const bool said = statusBar()->currentMessage().startsWith(nothing.left(nothing.indexOf('%')));
    if (!s.complete) return;
    const bool empty = std::none_of(s.tiles.begin(), s.tiles.end(),
                                    [](const auto& t) { return t && t->state != TileState::Empty; });
    // Everything hidden, or a new part: nothing to show, rightly. A grid of
    // no tiles is such a part's (an earlier revision's, published while a
    // file opened: it said "at the view feature size of 0 mm").
    if (empty && !s.layout.empty() && !partBounds(session_->document()).isEmpty())
        showMessage(nothing.arg(s.layout.voxelSize), 0);
    else if (said) statusBar()->clearMessage(); // shown again: the message is stale
}

void MainWindow::updateStatus()
{
    const auto snap = voxelizer_->latest();
    status_->show(voxelizer_->progress(), snap.get(), voxelizer_->lastStats(), viewport_->status(), memoryBudgetBytes(),
                  gpuLayout_ ? &*gpuLayout_ : nullptr);
}

} // namespace kerf::ui
