// The Edit and Add menus' commands: add a feature, group, delete,
// duplicate, add reference meshes. Each is one undoable step through the
// DocumentSession; where a feature goes and what it starts with, how a
// selection is grouped and how a mesh is referenced are the core's rules
// (AddFeature.hpp, DocumentEdits.hpp).

#include "MainWindow.hpp"
#include "NodeText.hpp"
#include "kerf/document/AddFeature.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/NodeTypes.hpp"
#include "kerf/viewport/ReferenceMesh.hpp"

#include <QMessageBox>
#include <QPushButton>

#include <unordered_set>

namespace kerf::ui {

namespace fs = std::filesystem;

bool MainWindow::addFeature(NodeType type)
{
    // Where it goes and what it starts with: edit::addFeature (AddFeature.hpp).
    const std::vector<std::string> selection = selectedNodeIds();
    std::string id;
    QString error;
    const bool ok = session_->apply(tr("Add %1").arg(nodeTypeLabel(type)),
                                    [&](Document& d) { id = edit::addFeature(d, type, selection); }, &error);
    if (!ok) {
        showMessage(tr("Cannot add the %1: %2").arg(nodeTypeLabel(type).toLower(), error));
        return false;
    }
    selectNodes({id});
    return true;
}

bool MainWindow::groupSelection(NodeType type)
{
    const std::vector<std::string> ids = selectedNodeIds();
    if (ids.empty()) {
        showMessage(tr("Select the features to group first."));
        return false;
    }
    const std::string id = edit::uniqueId(session_->document(), std::string(nodeTypeName(type)));
    QString error;
    const bool ok = session_->apply(tr("Group under %1").arg(nodeTypeLabel(type)),
                                    [&](Document& d) { edit::wrapNodes(d, ids, makeNode(type, id)); }, &error);
    if (!ok) {
        showMessage(tr("Cannot group: %1").arg(error));
        return false;
    }
    selectNodes({id});
    return true;
}

bool MainWindow::deleteSelection()
{
    std::vector<std::string> ids = selectedNodeIds();
    if (ids.empty()) return false;
    const Node* only = ids.size() == 1 ? session_->document().root.find(ids.front()) : nullptr;
    QString step = only ? tr("Delete %1").arg(featureName(*only)) : tr("Delete %1 features").arg(ids.size());
    // A mirror, an array or a group whose only child goes acts on nothing:
    // it goes too, and the step says so (a newcomer's deletion of a
    // mirrored leg was refused with "a mirror needs at least 1 child").
    // Asked again after each answer below: a difference deleted whole may
    // be a mirror's only child.
    std::vector<std::string> emptied;
    const auto takeEmptiedAlong = [&] {
        for (const std::string& id : edit::emptiedByRemoving(session_->document(), ids)) {
            emptied.push_back(id);
            ids.push_back(id);
        }
    };
    takeEmptiedAlong();
    // What other features' expressions refer to cannot go: said before any
    // question, with every use (it was refused after the question about the
    // difference, naming one).
    if (const std::vector<std::string> uses = edit::nodeUses(session_->document(), ids); !uses.empty()) {
        // Until the next edit: six seconds in the status bar were missed.
        showMessageUntilEdit(tr("Cannot delete: %1 %2 used by %3: change those first.")
                        .arg(only ? featureName(*only) : tr("these features"), only ? tr("is") : tr("are"),
                             describeExpressionUses(session_->document().root, uses)));
        return false;
    }
    // Deleting what a difference cuts from would make its first tool the
    // body: holes would come back as pegs, without a word. Each such
    // difference is asked about first (the whole of it, or only what was
    // selected).
    std::unordered_set<std::string> answered;
    for (;;) {
        Document trial = session_->document();
        try {
            edit::removeNodes(trial, ids);
        } catch (const std::exception&) {
            break; // refused below, with the reason
        }
        std::string changed;
        for (const std::string& id : edit::differencesWithNewBase(session_->document(), trial))
            if (!answered.count(id)) {
                changed = id;
                break;
            }
        if (changed.empty()) break;
        answered.insert(changed);
        switch (askDeletingABase(*session_->document().root.find(changed), trial.root.find(changed))) {
        case BaseDeletion::Cancel: return false;
        case BaseDeletion::WholeDifference:
            ids.push_back(changed);
            takeEmptiedAlong();
            // One feature selected and its difference taken whole: the step
            // names what goes, the difference ("Delete Left side with
            // groove", not "Delete Left side").
            if (only) step = tr("Delete %1").arg(featureName(*session_->document().root.find(changed)));
            break;
        case BaseDeletion::OnlySelection: break;
        }
    }
    if (!emptied.empty())
        step += tr(" and %1, left empty").arg(featureName(*session_->document().root.find(emptied.front())));
    QString error;
    const bool ok =
        session_->apply(step, [&](Document& d) { edit::removeNodes(d, ids); }, &error);
    if (!ok) showMessageUntilEdit(tr("Cannot delete: %1").arg(error));
    else if (!emptied.empty()) showMessage(step + tr(" (Undo brings them back)."));
    return ok;
}

MainWindow::BaseDeletion MainWindow::askDeletingABase(const Node& difference, const Node* after)
{
    const auto sentence = [](QString text) {
        if (!text.isEmpty()) text[0] = text[0].toUpper();
        return text;
    };
    // A difference left with no child at all goes with the deletion
    // (emptiedByRemoving), unless it is the part itself, which may be empty.
    if (!after || after->children.empty()) return BaseDeletion::OnlySelection;
    const QString base = featureName(difference.children.front());
    const QString name = featureName(difference);
    QMessageBox ask(QMessageBox::Warning, tr("Delete the base?"),
                    sentence(tr("%1 is what %2 cuts from.").arg(base, name)), QMessageBox::NoButton, this);
    ask.setObjectName("delete.base");
    ask.setInformativeText(tr("Without it, %1 would cut from %2 instead: what it cuts away would become solid.")
                               .arg(name, featureName(after->children.front())));
    QPushButton* whole = nullptr;
    if (&difference != &session_->document().root) {
        whole = ask.addButton(tr("Delete %1 too").arg(name), QMessageBox::DestructiveRole);
        whole->setObjectName("delete.base.whole");
    }
    QPushButton* onlySelection = ask.addButton(tr("Delete only the selection"), QMessageBox::DestructiveRole);
    onlySelection->setObjectName("delete.base.only");
    QPushButton* cancel = ask.addButton(QMessageBox::Cancel);
    cancel->setObjectName("delete.base.cancel");
    ask.setDefaultButton(cancel);
    ask.setEscapeButton(cancel);
    ask.exec();
    if (whole && ask.clickedButton() == whole) return BaseDeletion::WholeDifference;
    if (ask.clickedButton() == onlySelection) return BaseDeletion::OnlySelection;
    return BaseDeletion::Cancel;
}

bool MainWindow::duplicateSelection()
{
    const std::vector<std::string> ids = selectedNodeIds();
    if (ids.empty()) return false;
    std::vector<std::string> copies;
    QString error;
    const bool ok = session_->apply(tr("Duplicate"),
                                    [&](Document& d) {
                                        copies.clear();
                                        for (const auto& id : ids) copies.push_back(edit::duplicateNode(d, id));
                                    },
                                    &error);
    if (!ok) {
        showMessage(tr("Cannot duplicate: %1").arg(error));
        return false;
    }
    selectNodes(copies);
    return true;
}

void MainWindow::addMeshFiles(const QStringList& files)
{
    if (files.isEmpty()) return;
    QString error;
    const std::optional<fs::path> folder = session_->path() ? std::optional(session_->path()->parent_path()) : std::nullopt;
    const bool ok = session_->apply(tr("Add reference mesh"),
                                    [&](Document& d) {
                                        for (const QString& f : files) {
                                            // Check it loads first: a broken mesh is named, not added.
                                            loadTriangleMesh(f.toStdString());
                                            edit::addMeshReference(d, f.toStdString(), folder);
                                        }
                                    },
                                    &error);
    if (!ok) showMessage(tr("Cannot add the mesh: %1").arg(error));
}

} // namespace kerf::ui
