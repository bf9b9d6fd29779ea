#include "FeatureTreeModel.hpp"

#include "NodeText.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/NodeBounds.hpp"

#include <QColor>
#include <QIODevice>
#include <QMimeData>
#include <QPixmap>

namespace kerf::ui {

FeatureTreeModel::FeatureTreeModel(DocumentSession* session, QObject* parent) : QAbstractItemModel(parent), session_(session)
{
    items_ = flatten();
    for (std::string& id : toolsCuttingNothing(session_->document())) cutNothing_.insert(std::move(id));
    connect(session_, &DocumentSession::documentChanged, this, [this] {
        cutNothing_.clear();
        for (std::string& id : toolsCuttingNothing(session_->document())) cutNothing_.insert(std::move(id));
        // A change of values keeps the tree's shape: the rows stay (and the
        // view keeps its state); only a change of shape resets the model.
        std::vector<Item> next = flatten();
        const bool sameShape = next.size() == items_.size() &&
                               std::equal(next.begin(), next.end(), items_.begin(), [](const Item& a, const Item& b) {
                                   return a.id == b.id && a.parent == b.parent && a.row == b.row;
                               });
        if (sameShape) {
            items_ = std::move(next);
            emitChangedBelow(QModelIndex());
            return;
        }
        beginResetModel();
        items_ = std::move(next);
        endResetModel();
    });
}

void FeatureTreeModel::emitChangedBelow(const QModelIndex& parent)
{
    const int rows = rowCount(parent);
    if (rows == 0) return;
    emit dataChanged(index(0, 0, parent), index(rows - 1, ColumnCount - 1, parent));
    for (int r = 0; r < rows; ++r) emitChangedBelow(index(r, 0, parent));
}

std::vector<FeatureTreeModel::Item> FeatureTreeModel::flatten() const
{
    std::vector<Item> items;
    add(items, session_->document().root, -1, 0);
    return items;
}

void FeatureTreeModel::add(std::vector<Item>& items, const Node& n, int parent, int row)
{
    const int self = int(items.size());
    items.push_back({n.id, parent, row, {}});
    for (std::size_t i = 0; i < n.children.size(); ++i) {
        const int child = int(items.size());
        items[std::size_t(self)].children.push_back(child);
        add(items, n.children[i], self, int(i));
    }
}

const Node* FeatureTreeModel::nodeOf(const QModelIndex& index) const
{
    if (!index.isValid()) return nullptr;
    return session_->document().root.find(items_[std::size_t(index.internalId())].id);
}

QModelIndex FeatureTreeModel::indexOf(const std::string& nodeId, int column) const
{
    for (std::size_t i = 0; i < items_.size(); ++i)
        if (items_[i].id == nodeId) return createIndex(items_[i].row, column, quintptr(i));
    return {};
}

std::string FeatureTreeModel::nodeIdAt(const QModelIndex& index) const
{
    return index.isValid() ? items_[std::size_t(index.internalId())].id : std::string();
}

QModelIndex FeatureTreeModel::index(int row, int column, const QModelIndex& parent) const
{
    if (column < 0 || column >= ColumnCount || row < 0) return {};
    if (!parent.isValid()) return row == 0 ? createIndex(0, column, quintptr(0)) : QModelIndex();
    const Item& p = items_[std::size_t(parent.internalId())];
    if (row >= int(p.children.size())) return {};
    return createIndex(row, column, quintptr(p.children[std::size_t(row)]));
}

QModelIndex FeatureTreeModel::parent(const QModelIndex& child) const
{
    if (!child.isValid()) return {};
    const int p = items_[std::size_t(child.internalId())].parent;
    if (p < 0) return {};
    return createIndex(items_[std::size_t(p)].row, 0, quintptr(p));
}

int FeatureTreeModel::rowCount(const QModelIndex& parent) const
{
    if (!parent.isValid()) return items_.empty() ? 0 : 1;
    if (parent.column() != 0) return 0;
    return int(items_[std::size_t(parent.internalId())].children.size());
}

int FeatureTreeModel::columnCount(const QModelIndex&) const { return ColumnCount; }

QVariant FeatureTreeModel::data(const QModelIndex& index, int role) const
{
    const Node* n = nodeOf(index);
    if (!n) return {};
    if (role == NodeIdRole) return QString::fromStdString(n->id);
    if (index.column() == TypeColumn) {
        if (role != Qt::DisplayRole && role != Qt::ForegroundRole && role != Qt::ToolTipRole) return {};
        // In a difference the order matters: the first child is the body,
        // the others are cut from it.
        const Node* parent = nodeOf(index.parent());
        if (parent && parent->type == NodeType::Difference) {
            if (index.row() == 0) return role == Qt::DisplayRole ? tr("%1 · base").arg(nodeTypeLabel(n->type)) : QVariant();
            // A dowel hole moved off its board cuts nothing, and the part
            // and its file lack it without a word: said where it is listed.
            if (cutNothing_.contains(n->id)) {
                if (role == Qt::ForegroundRole) return QColor(0xb0, 0x00, 0x20);
                if (role == Qt::ToolTipRole)
                    return tr("%1 lies clear of %2: it cuts nothing from it.")
                        .arg(displayName(*n), displayName(parent->children.front()));
                return role == Qt::DisplayRole ? tr("%1 · cuts nothing").arg(nodeTypeLabel(n->type)) : QVariant();
            }
            return role == Qt::DisplayRole ? tr("%1 · cut").arg(nodeTypeLabel(n->type)) : QVariant();
        }
        return role == Qt::DisplayRole ? QVariant(nodeTypeLabel(n->type)) : QVariant();
    }
    switch (role) {
    case Qt::DisplayRole: return displayName(*n);
    case Qt::EditRole: return QString::fromStdString(n->name.value_or(n->id));
    case Qt::ToolTipRole:
        return tr("%1 '%2'%3").arg(nodeTypeLabel(n->type), QString::fromStdString(n->id),
                                   n->visible ? QString() : tr(" (hidden)"));
    case Qt::CheckStateRole: return n->visible ? Qt::Checked : Qt::Unchecked;
    case Qt::DecorationRole:
        if (n->color) {
            QPixmap swatch(12, 12);
            swatch.fill(QColor(n->color->r, n->color->g, n->color->b));
            return swatch;
        }
        return {};
    case Qt::ForegroundRole:
        if (!n->visible) return QColor(Qt::gray);
        return {};
    default: return {};
    }
}

QVariant FeatureTreeModel::headerData(int section, Qt::Orientation orientation, int role) const
{
    if (orientation != Qt::Horizontal || role != Qt::DisplayRole) return {};
    return section == NameColumn ? tr("Feature") : tr("Type");
}

Qt::ItemFlags FeatureTreeModel::flags(const QModelIndex& index) const
{
    const Node* n = nodeOf(index);
    if (!n) return Qt::ItemIsDropEnabled;
    Qt::ItemFlags f = Qt::ItemIsEnabled | Qt::ItemIsSelectable;
    if (index.column() == NameColumn) f |= Qt::ItemIsEditable | Qt::ItemIsUserCheckable;
    if (index.parent().isValid()) f |= Qt::ItemIsDragEnabled;
    if (!isPrimitive(n->type)) f |= Qt::ItemIsDropEnabled;
    return f;
}

bool FeatureTreeModel::setData(const QModelIndex& index, const QVariant& value, int role)
{
    const Node* n = nodeOf(index);
    if (!n) return false;
    const std::string id = n->id;
    QString error;
    bool ok = false;
    if (role == Qt::CheckStateRole) {
        const bool visible = value.toInt() == Qt::Checked;
        ok = session_->apply(visible ? tr("Show %1").arg(displayName(*n)) : tr("Hide %1").arg(displayName(*n)),
                             [&](Document& d) { d.root.find(id)->visible = visible; }, &error);
    } else if (role == Qt::EditRole) {
        const std::string name = value.toString().trimmed().toStdString();
        ok = session_->apply(tr("Rename %1").arg(displayName(*n)),
                             [&](Document& d) {
                                 Node* m = d.root.find(id);
                                 if (name.empty() || name == m->id) m->name.reset();
                                 else m->name = name;
                             },
                             &error);
    } else {
        return false;
    }
    if (!ok) emit editRefused(error);
    return ok;
}

QMimeData* FeatureTreeModel::mimeData(const QModelIndexList& indexes) const
{
    QStringList ids;
    for (const QModelIndex& i : indexes)
        if (i.column() == 0) ids << QString::fromStdString(nodeIdAt(i));
    auto* data = new QMimeData;
    data->setData(kMimeType, ids.join('\n').toUtf8());
    return data;
}

bool FeatureTreeModel::canDropMimeData(const QMimeData* data, Qt::DropAction action, int, int,
                                       const QModelIndex& parent) const
{
    if (action != Qt::MoveAction || !data->hasFormat(kMimeType)) return false;
    const Node* target = nodeOf(parent);
    return target && !isPrimitive(target->type);
}

bool FeatureTreeModel::dropMimeData(const QMimeData* data, Qt::DropAction action, int row, int,
                                    const QModelIndex& parent)
{
    if (!canDropMimeData(data, action, row, 0, parent)) return false;
    const std::string target = nodeIdAt(parent);
    const QStringList ids = QString::fromUtf8(data->data(kMimeType)).split('\n', Qt::SkipEmptyParts);
    std::size_t at = row < 0 ? std::size_t(-1) : std::size_t(row);
    QString error;
    const auto move = [&](Document& d) {
        std::size_t index = at;
        for (const QString& id : ids) {
            const std::string s = id.toStdString();
            edit::moveNode(d, s, target, index);
            // Later ones go after the one just moved.
            if (const auto to = edit::locate(d, s)) index = to->index + 1;
        }
    };
    // A move that changes what a difference cuts from asks first.
    if (confirm_) {
        Document trial = session_->document();
        try {
            move(trial);
        } catch (const std::exception&) {
            // refused below, with the reason
        }
        const std::string changed = edit::differenceWithNewBase(session_->document(), trial);
        if (const Node* d = changed.empty() ? nullptr : trial.root.find(changed)) {
            const QString question =
                d->children.empty()
                    ? tr("%1 would be left with nothing to cut from. Move anyway?").arg(featureName(*d))
                    : tr("%1 would cut from %2 instead: what was the body becomes a tool, and the part may "
                         "empty. Move anyway?")
                          .arg(featureName(*d), featureName(d->children.front()));
            if (!confirm_(question)) return false;
        }
    }
    const Node* first = ids.size() == 1 ? session_->document().root.find(ids.front().toStdString()) : nullptr;
    const bool ok = session_->apply(first ? tr("Move %1").arg(featureName(*first))
                                          : tr("Move %1 features").arg(ids.size()),
                                    move, &error);
    if (!ok) emit editRefused(error);
    // The session's change resets the model; returning false keeps the view
    // from removing the dragged rows itself.
    return false;
}

} // namespace kerf::ui
