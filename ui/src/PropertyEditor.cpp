#include "PropertyEditor.hpp"

#include "NodeText.hpp"
#include "Expression.hpp"
#include "LengthDisplay.hpp"
#include "NameCompleter.hpp"
#include "QuantityEdit.hpp"
#include "TypingStaysInTable.hpp"
#include "kerf/document/Expression.hpp"
#include "kerf/document/AddFeature.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/DocumentError.hpp"
#include "UndoKeysToWindow.hpp"

#include "kerf/document/NodeTypes.hpp"
#include "kerf/document/ReferableNumbers.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/voxelizer/GridLayout.hpp"

#include <QAction>
#include <QCheckBox>
#include <QCoreApplication>
#include <QColorDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPointer>
#include <QLineEdit>
#include <QPushButton>
#include <QSignalBlocker>
#include <QTableWidget>
#include <QVBoxLayout>

#include <glm/glm.hpp>

#include <cmath>

namespace kerf::ui {

namespace {

constexpr int kLength = int(QuantityEdit::Unit::Length);
constexpr int kDeg = int(QuantityEdit::Unit::Degrees);
constexpr int kPlain = int(QuantityEdit::Unit::None);
const char* kAxes[3] = {"x", "y", "z"};

QLabel* errorLabel(QWidget* parent)
{
    auto* l = new QLabel(parent);
    l->setWordWrap(true);
    l->setStyleSheet(QStringLiteral("color: #c0392b;"));
    l->setVisible(false);
    return l;
}

// A unit normal from a vector whose one component was just typed: the
// document holds unit normals (the reader normalises them), so the edit does
// too; a zero vector is left for validation to refuse.
void setNormalComponent(glm::dvec3& n, int axis, double v)
{
    n[axis] = v;
    const double len = glm::length(n);
    if (len > 0.0 && std::isfinite(len)) n /= len;
}

// A profile cell's expression ("-length/2", without the '='), where one
// drives the coordinate.
constexpr int kExpressionRole = Qt::UserRole + 1;

// A profile point's coordinate as shown and typed: a length in the user's unit.
QString profileText(double mm)
{
    return QString::fromStdString(lengthForEditing(mm, LengthDisplay::instance().unit()));
}

std::optional<double> profileValue(const QTableWidgetItem* item)
{
    if (!item) return std::nullopt;
    return evaluateLength(item->text().toStdString(), LengthDisplay::instance().unit()).value;
}

} // namespace

PropertyEditor::PropertyEditor(DocumentSession* session, QWidget* parent) : QWidget(parent), session_(session)
{
    auto* outer = new QVBoxLayout(this);
    title_ = new QLabel(this);
    title_->setObjectName("properties.title");
    title_->setStyleSheet(QStringLiteral("font-weight: bold;"));
    outer->addWidget(title_);
    auto* body = new QWidget(this);
    form_ = new QFormLayout(body);
    form_->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
    outer->addWidget(body);
    outer->addStretch(1);
    connect(session_, &DocumentSession::documentChanged, this, [this] {
        // A refusal is about the document as it was: any change (an undo,
        // an edit elsewhere) makes it stale ("point 4: not a number" stayed
        // after Undo). A refused edit changes nothing, and keeps its message.
        showError(nullptr, QString());
        const Node* n = session_->document().root.find(nodeId_);
        if (!n || n->type != shownType_) rebuild();
        else refresh();
    });
    connect(&LengthDisplay::instance(), &LengthDisplay::changed, this, &PropertyEditor::rebuild); // headers too
    rebuild();
}

void PropertyEditor::setNode(const std::string& nodeId)
{
    if (nodeId == nodeId_ && selected_ <= 1) return;
    nodeId_ = nodeId;
    selected_ = nodeId.empty() ? 0 : 1;
    rebuild();
}

void PropertyEditor::setSelection(const std::vector<std::string>& nodeIds)
{
    if (nodeIds.size() <= 1) {
        setNode(nodeIds.empty() ? std::string() : nodeIds.front());
        return;
    }
    if (nodeId_.empty() && selected_ == nodeIds.size()) return;
    nodeId_.clear();
    selected_ = nodeIds.size();
    rebuild();
}

QString PropertyEditor::errorFor(const QString& field) const
{
    for (const Field& f : fields_)
        if (f.key == field) return f.error->isHidden() ? QString() : f.error->text();
    if (field == "profile" && profileError_) return profileError_->isHidden() ? QString() : profileError_->text();
    if (field == "name" && generalError_) return generalError_->isHidden() ? QString() : generalError_->text();
    if (field == "part.featureSize" && partError_) return partError_->isHidden() ? QString() : partError_->text();
    return {};
}

void PropertyEditor::showError(QLabel* error, const QString& message)
{
    // One message at a time, under the field it is about: an edit that
    // went through or a new refusal elsewhere makes older ones stale.
    std::vector<QLabel*> all{generalError_, profileError_, partError_};
    for (const Field& f : fields_)
        all.push_back(f.error);
    for (QLabel* other : all)
        if (other && other != error) other->hide();
    if (!error) return; // (none: every message goes)
    error->setText(message);
    error->setVisible(!message.isEmpty());
}

bool PropertyEditor::applyToNode(const QString& text, const std::function<void(Node&)>& change, QLabel* error,
                                 const QString& mergeKey)
{
    const std::string id = nodeId_;
    QString why;
    const bool ok = session_->apply(
        text,
        [&](Document& d) {
            const Node* n = d.root.find(id);
            if (!n) throw std::invalid_argument("the node is gone");
            // Through updateNode: a number typed over a field an expression
            // drives replaces the expression (else resolving would put it back).
            Node updated = *n;
            change(updated);
            edit::updateNode(d, id, updated);
            // A primitive resting on the grid stays on it, judged on the
            // values its expressions give (a height typed as "=leg_l" left
            // a new leg half under the grid).
            if (!updated.expressions.empty()) {
                const Document resolved = d.resolved();
                if (const Node* r = resolved.root.find(id)) updated = *r;
            }
            Node placed = updated;
            edit::keepResting(*n, placed);
            Node& target = *d.root.find(id);
            if (placed.transform.translate.z != updated.transform.translate.z)
                target.transform.translate.z = placed.transform.translate.z;
            // ... and by the expression that keeps it there (Size Z "=thickness").
            const std::string positionZ = "transform.translate[2]";
            if (const auto e = placed.expressions.find(positionZ); e != placed.expressions.end())
                target.expressions[positionZ] = e->second;
            else
                target.expressions.erase(positionZ);
        },
        &why, mergeKey);
    if (error) showError(error, ok ? QString() : why);
    return ok;
}

void PropertyEditor::commit(std::size_t index, double value, bool step)
{
    if (refreshing_ || index >= fields_.size()) return;
    const Node* n = session_->document().root.find(nodeId_);
    if (!n) return;
    // Copies: the edit's signals may rebuild the fields.
    const QString key = fields_[index].key;
    // Undo's menu item names the field as its row does, never the file's key.
    QString field = fields_[index].label;
    if (field.size() > 1 && field[1].isLower()) field[0] = field[0].toLower(); // "Position X" -> "position X"
    const auto set = fields_[index].set;
    const auto get = fields_[index].get;
    QPointer<QuantityEdit> edit = fields_[index].edit;
    QPointer<QLabel> error = fields_[index].error;
    const QString label = tr("Set %1 of %2").arg(field, featureName(*n));
    QString why;
    const std::string id = nodeId_;
    const bool ok = session_->apply(
        label,
        [&](Document& d) {
            const Node* m = d.root.find(id);
            if (!m) throw std::invalid_argument("the node is gone");
            Node updated = *m; // through updateNode, as applyToNode
            set(updated, value);
            edit::keepResting(*m, updated);
            edit::updateNode(d, id, updated);
        },
        // Steps of the arrows or the wheel merge into one undo step; values
        // typed and entered are a step each (510 then 520, undone, is 510).
        &why, step ? QString::fromStdString(id) + "/" + key : QString());
    if (error) showError(error, ok ? QString() : why);
    // Refused: the field shows the document's value again (and the
    // expression that drives it), the reason stays.
    if (!ok && edit)
        if (const Node* now = session_->document().root.find(id)) {
            const auto driven = now->expressions.find(expressionPath(key).toStdString());
            edit->showDocument(get(*now), driven == now->expressions.end() ? QString()
                                                                           : QString::fromStdString(driven->second));
        }
}

QString PropertyEditor::expressionPath(const QString& key)
{
    // "translate.x" -> "transform.translate[0]", "size.z" -> "size[2]", "radius" -> "radius".
    const qsizetype dot = key.indexOf('.');
    if (dot < 0) return key;
    const QString base = key.left(dot), axis = key.mid(dot + 1);
    const int index = axis == "x" ? 0 : axis == "y" ? 1 : 2;
    const QString path = base + "[" + QString::number(index) + "]";
    return base == "translate" || base == "rotate" ? "transform." + path : path;
}

QString PropertyEditor::expressionFor(const QString& key) const
{
    const Node* n = session_->document().root.find(nodeId_);
    if (!n) return {};
    const auto it = n->expressions.find(expressionPath(key).toStdString());
    return it == n->expressions.end() ? QString() : QString::fromStdString(it->second);
}

void PropertyEditor::addQuantity(const QString& label, const QString& key, int unit,
                                 std::function<double(const Node&)> get, std::function<void(Node&, double)> set,
                                 int decimals)
{
    auto* row = new QWidget(this);
    auto* v = new QVBoxLayout(row);
    v->setContentsMargins(0, 0, 0, 0);
    v->setSpacing(1);
    auto* edit = new QuantityEdit(QuantityEdit::Unit(unit), row);
    edit->setObjectName("field." + key);
    edit->setDecimals(decimals);
    // "=thi" offers "thickness", "=pan" "panel.size[2]": the names an expression can use.
    edit->completeNames([s = session_] { return parameterAndFeatureNames(s->document()); });
    auto* error = errorLabel(row);
    error->setObjectName("error." + key);
    v->addWidget(edit);
    v->addWidget(error);
    form_->addRow(label, row);
    fields_.push_back({key, label, edit, error, std::move(get), std::move(set)});
    const std::size_t index = fields_.size() - 1;
    connect(edit, &QuantityEdit::valueChanged, this,
            [this, index, edit](double value) { commit(index, value, edit->stepping()); });
    connect(edit, &QuantityEdit::unreadable, this, [this, index](const QString& why) {
        showError(fields_[index].error, why);
    });
    connect(edit, &QuantityEdit::expressionEntered, this,
            [this, index](const QString& expression) { commitExpression(index, expression); });
    // Esc took the typed text back: a refusal of it is no longer the field's.
    connect(edit, &QuantityEdit::reverted, this, [this, index] { showError(fields_[index].error, QString()); });
}

void PropertyEditor::commitExpression(std::size_t index, const QString& expression)
{
    if (refreshing_ || index >= fields_.size() || expression.isEmpty()) return;
    const Node* n = session_->document().root.find(nodeId_);
    if (!n) return;
    const std::string path = expressionPath(fields_[index].key).toStdString();
    const std::string text = expression.toStdString();
    QString field = fields_[index].label;
    if (field.size() > 1 && field[1].isLower()) field[0] = field[0].toLower();
    // "=depth - 2" stored in the document subtracts 2 mm: said before it
    // happens to someone who sees inches.
    if (fields_[index].edit->unit() == QuantityEdit::Unit::Length &&
        LengthDisplay::instance().unit() == LengthUnit::Inches && expr::addsBareNumbersToLengths(text)) {
        showError(fields_[index].error,
                  tr("In an expression a number without a unit is in millimetres, the document's unit: "
                     "write the unit (2in, 1/8in, 3mm)."));
        return;
    }
    // The document evaluates it (and refuses it, under the field, with its reason).
    applyToNode(tr("Set %1 of %2 to =%3").arg(field, featureName(*n), expression),
                [&](Node& m) { m.expressions[path] = text; }, fields_[index].error);
}

void PropertyEditor::addVector(const QString& label, const QString& key, int unit,
                               std::function<glm::dvec3(const Node&)> get, std::function<void(Node&, int, double)> set,
                               int decimals)
{
    for (int a = 0; a < 3; ++a)
        addQuantity(QStringLiteral("%1 %2").arg(label, QString(kAxes[a]).toUpper()), key + "." + kAxes[a], unit,
                    [get, a](const Node& n) { return get(n)[a]; },
                    [set, a](Node& n, double v) { set(n, a, v); }, decimals);
}

void PropertyEditor::rebuild()
{
    // Remove the old rows. Later, not now: this may run inside a signal of
    // one of their own widgets (an edit that changed the node's type).
    while (form_->rowCount() > 0) {
        const QFormLayout::TakeRowResult row = form_->takeRow(0);
        for (QLayoutItem* item : {row.labelItem, row.fieldItem}) {
            if (!item) continue;
            if (QWidget* w = item->widget()) {
                w->hide();
                w->deleteLater();
            }
            delete item;
        }
    }
    fields_.clear();
    name_ = nullptr;
    visible_ = nullptr;
    color_ = nullptr;
    profile_ = nullptr;
    profileField_ = nullptr;
    profileError_ = nullptr;
    generalError_ = nullptr;
    partFeatureSize_ = nullptr;
    partError_ = nullptr;
    const Node* n = session_->document().root.find(nodeId_);
    if (!n && selected_ > 1) {
        title_->setText(tr("%1 features selected").arg(selected_));
        auto* note = new QLabel(tr("Select one to see and edit its properties. Delete, and Add > Group Selection "
                                   "Under, take them all."),
                                this);
        note->setObjectName("properties.note");
        note->setWordWrap(true);
        form_->addRow(note);
        return;
    }
    if (!n) {
        nodeId_.clear();
        selected_ = 0;
        title_->setText(tr("Nothing selected — the part"));
        addPartSettings();
        refresh();
        return;
    }
    shownType_ = n->type;

    name_ = new QLineEdit(this);
    name_->setObjectName("field.name");
    name_->setPlaceholderText(QString::fromStdString(n->id));
    UndoKeysToWindow::install(name_);
    // Esc takes back a name typed and not entered, as in the number fields
    // (a newcomer's Esc kept "Pin hole XYZ", renamed on leaving the field).
    auto* revertName = new QAction(name_);
    revertName->setShortcut(Qt::Key_Escape);
    revertName->setShortcutContext(Qt::WidgetShortcut);
    name_->addAction(revertName);
    connect(revertName, &QAction::triggered, this, [this] {
        const Node* shown = session_->document().root.find(nodeId_);
        name_->setText(shown && shown->name ? QString::fromStdString(*shown->name) : QString());
        name_->setModified(false);
        name_->selectAll();
    });
    form_->addRow(tr("Name"), name_);
    // The id expressions refer to the feature by (a named feature shows its
    // name everywhere else, and a newcomer could not find "stile-left").
    auto* id = new QLabel(QString::fromStdString(n->id), this);
    id->setObjectName("field.id");
    id->setTextInteractionFlags(Qt::TextSelectableByMouse);
    id->setToolTip(tr("Other features' expressions refer to this one's numbers by its id: =%1")
                       .arg(QString::fromStdString(referableNumbers(*n).front())));
    form_->addRow(tr("Id"), id);
    generalError_ = errorLabel(this);
    form_->addRow(QString(), generalError_);
    connect(name_, &QLineEdit::editingFinished, this, [this] {
        if (refreshing_) return;
        const std::string text = name_->text().trimmed().toStdString();
        name_->setModified(false); // committed: Ctrl+Z now undoes the rename (UndoKeysToWindow)
        applyToNode(tr("Rename"), [&](Node& m) {
            if (text.empty() || text == m.id) m.name.reset();
            else m.name = text;
        }, generalError_);
    });
    visible_ = new QCheckBox(tr("Visible"), this);
    visible_->setObjectName("field.visible");
    form_->addRow(QString(), visible_);
    connect(visible_, &QCheckBox::toggled, this, [this](bool on) {
        if (refreshing_) return;
        applyToNode(on ? tr("Show") : tr("Hide"), [&](Node& m) { m.visible = on; }, generalError_);
    });
    auto* colorRow = new QWidget(this);
    auto* ch = new QHBoxLayout(colorRow);
    ch->setContentsMargins(0, 0, 0, 0);
    color_ = new QPushButton(colorRow);
    color_->setObjectName("field.color");
    auto* clear = new QPushButton(tr("Use Parent's"), colorRow);
    clear->setToolTip(tr("Use the parent's colour (or the default wood tone)"));
    ch->addWidget(color_, 1);
    ch->addWidget(clear);
    form_->addRow(tr("Colour"), colorRow);
    connect(color_, &QPushButton::clicked, this, [this] {
        const Node* m = session_->document().root.find(nodeId_);
        if (!m) return;
        const QColor start = m->color ? QColor(m->color->r, m->color->g, m->color->b) : QColor(181, 125, 77);
        const QColor c = QColorDialog::getColor(start, this, tr("Colour of %1").arg(displayName(*m)));
        if (!c.isValid()) return;
        applyToNode(tr("Colour"), [&](Node& x) {
            x.color = Color{std::uint8_t(c.red()), std::uint8_t(c.green()), std::uint8_t(c.blue())};
        }, generalError_);
    });
    connect(clear, &QPushButton::clicked, this,
            [this] { applyToNode(tr("Inherit colour"), [](Node& x) { x.color.reset(); }, generalError_); });

    addVector(tr("Position"), "translate", kLength, [](const Node& m) { return m.transform.translate; },
              [](Node& m, int a, double v) { m.transform.translate[a] = v; });
    addVector(tr("Rotation"), "rotate", kDeg, [](const Node& m) { return m.transform.rotate; },
              [](Node& m, int a, double v) { m.transform.rotate[a] = v; });

    // The type's own fields, as its row of the node type table lists them.
    for (const FieldSpec& f : nodeTypeSpec(n->type).fields) {
        const QString label = QCoreApplication::translate("NodeTypes", std::string(f.label).c_str());
        const QString key = QString::fromUtf8(f.key.data(), qsizetype(f.key.size()));
        const int unit = f.unit == FieldUnit::Length ? kLength : f.unit == FieldUnit::Angle ? kDeg : kPlain;
        const FieldSpec* spec = &f; // the table lives as long as the program
        const int firstRow = form_->rowCount();
        switch (f.shape) {
        case FieldShape::Number:
            addQuantity(label, key, unit, [spec](const Node& m) { return spec->numberIn(m); },
                        [spec](Node& m, double v) { spec->numberIn(m) = v; });
            break;
        case FieldShape::Vector:
            addVector(label, key, unit, [spec](const Node& m) { return spec->vectorIn(m); },
                      [spec](Node& m, int a, double v) { spec->vectorIn(m)[a] = v; });
            break;
        case FieldShape::Direction:
            addVector(label, key, unit, [spec](const Node& m) { return spec->vectorIn(m); },
                      [spec](Node& m, int a, double v) { setNormalComponent(spec->vectorIn(m), a, v); });
            addAxisButtons(label, key, *spec);
            break;
        case FieldShape::Counts:
            addVector(label, key, unit,
                      [spec](const Node& m) {
                          const auto& c = spec->countsIn(m);
                          return glm::dvec3(double(c[0]), double(c[1]), double(c[2]));
                      },
                      [spec, key](Node& m, int a, double v) {
                          // A count is whole: 2.5 is refused beside the
                          // field, not rounded to 3 without a word (a
                          // newcomer's Count Z; the field had no decimals).
                          if (v != std::floor(v))
                              throw DocumentError("", m.id, key.toStdString() + "[" + std::to_string(a) + "]",
                                                  "must be a whole number, not " + QString::number(v).toStdString());
                          spec->countsIn(m)[std::size_t(a)] = std::llround(v);
                      });
            break;
        case FieldShape::Points: addProfileTable(*spec); break;
        }
        // The field's meaning on every widget of its rows.
        const QString help = QCoreApplication::translate("NodeTypes", std::string(f.help).c_str());
        for (int r = firstRow; r < form_->rowCount(); ++r)
            if (QLayoutItem* item = form_->itemAt(r, QFormLayout::FieldRole); item && item->widget())
                item->widget()->setToolTip(help);
    }
    refresh();
}

void PropertyEditor::addAxisButtons(const QString& label, const QString& key, const FieldSpec& field)
{
    // A mirror's normal turned from X to Y one field at a time passes
    // through (0, 0, 0), which no plane has: a newcomer had to find that Y
    // goes first. One click sets a direction along an axis.
    auto* row = new QWidget(this);
    auto* h = new QHBoxLayout(row);
    h->setContentsMargins(0, 0, 0, 0);
    const FieldSpec* spec = &field;
    for (int a = 0; a < 3; ++a) {
        const QString axis = QString(kAxes[a]).toUpper();
        auto* button = new QPushButton(tr("Along %1").arg(axis), row);
        button->setObjectName(QString("field.%1.along.%2").arg(key, QString(kAxes[a])));
        button->setToolTip(tr("%1 along the %2 axis").arg(label, axis));
        connect(button, &QPushButton::clicked, this, [this, spec, a, label, axis] {
            const Node* n = session_->document().root.find(nodeId_);
            if (!n) return;
            QString named = label; // "Normal" -> "normal", as the other steps name a field
            if (named.size() > 1 && named[1].isLower()) named[0] = named[0].toLower();
            applyToNode(tr("Set %1 of %2 along %3").arg(named, featureName(*n), axis), [spec, a](Node& m) {
                glm::dvec3 along(0.0);
                along[a] = 1.0;
                spec->vectorIn(m) = along;
            }, generalError_);
        });
        h->addWidget(button);
    }
    h->addStretch();
    form_->addRow(QString(), row);
}

void PropertyEditor::addProfileTable(const FieldSpec& field)
{
    profileField_ = &field;
    profile_ = new QTableWidget(0, 2, this);
    profile_->setObjectName("field." + QString::fromUtf8(field.key.data(), qsizetype(field.key.size())));
    const QString a = QString::fromUtf8(field.pointAxes[0].data(), qsizetype(field.pointAxes[0].size())).toUpper();
    const QString b = QString::fromUtf8(field.pointAxes[1].data(), qsizetype(field.pointAxes[1].size())).toUpper();
    const QString unit = LengthDisplay::instance().unit() == LengthUnit::Inches ? tr("in") : tr("mm");
    profile_->setHorizontalHeaderLabels({tr("%1 (%2)").arg(a, unit), tr("%1 (%2)").arg(b, unit)});
    profile_->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
    // Eight points in sight (it showed five of an 18-point outline).
    profile_->setMinimumHeight(profile_->horizontalHeader()->sizeHint().height() + 8 * (fontMetrics().height() + 8) + 4);
    // Typing over a point's cell edits it, as in the Parameters table.
    profile_->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed |
                              QAbstractItemView::AnyKeyPressed);
    TypingStaysInTable::install(profile_);
    form_->addRow(QCoreApplication::translate("NodeTypes", std::string(field.label).c_str()), profile_);
    auto* buttons = new QWidget(this);
    auto* h = new QHBoxLayout(buttons);
    h->setContentsMargins(0, 0, 0, 0);
    auto* add = new QPushButton(tr("Add point"), buttons);
    add->setObjectName("profile.add");
    auto* remove = new QPushButton(tr("Remove point"), buttons);
    remove->setObjectName("profile.remove");
    h->addWidget(add);
    h->addWidget(remove);
    form_->addRow(QString(), buttons);
    profileError_ = errorLabel(this);
    profileError_->setObjectName("error.profile");
    form_->addRow(QString(), profileError_);
    connect(profile_, &QTableWidget::cellChanged, this, [this](int row, int column) {
        if (refreshing_) return;
        // "=-length/2" drives the coordinate; a number typed over a driven
        // one replaces its expression (as in the fields above).
        if (QTableWidgetItem* item = profile_->item(row, column)) {
            const QString text = item->text().trimmed();
            const QSignalBlocker block(profile_);
            item->setData(kExpressionRole, text.startsWith('=') ? QVariant(text.mid(1).trimmed()) : QVariant());
        }
        commitProfile();
    });
    connect(add, &QPushButton::clicked, this, [this] {
        // A new point halfway along the edge after the current row.
        const int r = std::max(0, profile_->currentRow());
        const int n = profile_->rowCount();
        if (n < 2) return;
        const int next = (r + 1) % n;
        auto cell = [&](int row, int col) { return profileValue(profile_->item(row, col)).value_or(0.0); };
        const double x = 0.5 * (cell(r, 0) + cell(next, 0)), y = 0.5 * (cell(r, 1) + cell(next, 1));
        {
            const QSignalBlocker block(profile_);
            profile_->insertRow(r + 1);
            profile_->setItem(r + 1, 0, new QTableWidgetItem(profileText(x)));
            profile_->setItem(r + 1, 1, new QTableWidgetItem(profileText(y)));
            // The new point is current: pressed again, Add point walks on
            // along the outline (it halved the same edge again and again).
            profile_->setCurrentCell(r + 1, 0);
        }
        commitProfile();
    });
    connect(remove, &QPushButton::clicked, this, [this] {
        const int r = profile_->currentRow();
        if (r < 0) return;
        {
            const QSignalBlocker block(profile_);
            profile_->removeRow(r);
        }
        commitProfile();
    });
}

void PropertyEditor::commitProfile()
{
    std::vector<glm::dvec2> points;
    std::vector<std::array<std::string, 2>> driven;
    const bool inches = LengthDisplay::instance().unit() == LengthUnit::Inches;
    for (int r = 0; r < profile_->rowCount(); ++r) {
        glm::dvec2 p(0.0);
        std::array<std::string, 2> expressions;
        for (int c = 0; c < 2; ++c) {
            const QTableWidgetItem* item = profile_->item(r, c);
            const QString expression = item ? item->data(kExpressionRole).toString() : QString();
            if (!expression.isEmpty()) {
                expressions[std::size_t(c)] = expression.toStdString();
                if (inches && expr::addsBareNumbersToLengths(expressions[std::size_t(c)])) {
                    showError(profileError_, tr("point %1: in an expression a number without a unit is in "
                                                "millimetres, the document's unit: write the unit (2in, 1/8in, 3mm).")
                                                 .arg(r + 1));
                    return;
                }
                continue; // its number comes from resolving the document
            }
            const std::optional<double> v = profileValue(item);
            if (!v) {
                // Said, and the typed text kept to be mended (it was lost).
                showError(profileError_, tr("point %1: not a number").arg(r + 1));
                return;
            }
            p[c] = *v;
        }
        points.push_back(p);
        driven.push_back(expressions);
    }
    const std::string id = nodeId_;
    QString why;
    const bool ok = session_->apply(tr("Edit profile"),
                                    [&](Document& d) { edit::setProfile(d, id, points, driven); }, &why);
    // Refused (a point typed that makes the outline cross itself until its
    // other coordinate is typed too): the table keeps what was typed, and
    // the part its last profile, until the outline is whole again.
    showError(profileError_, ok ? QString() : tr("%1 (not applied: the part keeps its last profile)").arg(why));
}

void PropertyEditor::addPartSettings()
{
    partFeatureSize_ = new QuantityEdit(QuantityEdit::Unit::Millimetres, this);
    partFeatureSize_->setObjectName("part.featureSize");
    partFeatureSize_->setDecimals(4);
    partFeatureSize_->setSingleStep(0.1);
    partFeatureSize_->setToolTip(tr("The smallest feature the view resolves: a 5 mm hole needs about 0.5 mm to look "
                                    "round. Smaller is sharper and slower. Saved with the document; the export "
                                    "dialog has its own."));
    form_->addRow(tr("View feature size"), partFeatureSize_);
    partError_ = errorLabel(this);
    partError_->setObjectName("error.part.featureSize");
    form_->addRow(QString(), partError_);
    connect(partFeatureSize_, &QuantityEdit::unreadable, this, [this](const QString& why) { showError(partError_, why); });
    connect(partFeatureSize_, &QuantityEdit::valueChanged, this, [this](double value) {
        if (refreshing_) return;
        QString why;
        const bool ok = session_->apply(
            tr("Set the view's feature size"), [&](Document& d) { d.settings.featureSize = value; }, &why,
            QStringLiteral("settings.feature_size"));
        if (partError_) showError(partError_, ok ? QString() : why);
        if (!ok) refresh(); // the document's value again
    });
}

void PropertyEditor::refresh()
{
    const Node* n = session_->document().root.find(nodeId_);
    if (partFeatureSize_ && !partFeatureSize_->hasFocus()) {
        const Document& doc = session_->document();
        refreshing_ = true;
        partFeatureSize_->showValue(
            doc.settings.featureSize.value_or(defaultFeatureSize(compileTape(doc).bounds())));
        refreshing_ = false;
    }
    if (!n) return;
    refreshing_ = true;
    // The feature's name as it is now ("Box — Side" once renamed; it kept
    // the id a newcomer had renamed away).
    title_->setText(tr("%1 — %2").arg(nodeTypeLabel(n->type), displayName(*n)));
    if (name_ && !name_->hasFocus()) name_->setText(n->name ? QString::fromStdString(*n->name) : QString());
    if (visible_) visible_->setChecked(n->visible);
    if (color_) {
        if (n->color) {
            const QColor c(n->color->r, n->color->g, n->color->b);
            color_->setText(c.name());
            color_->setStyleSheet(QStringLiteral("background: %1; color: %2;")
                                      .arg(c.name(), c.lightness() > 128 ? "black" : "white"));
        } else {
            color_->setText(tr("Parent's — choose…"));
            color_->setStyleSheet({});
        }
    }
    for (Field& f : fields_) {
        // The field just entered too (it keeps the focus after Enter): an
        // expression entered there showed the value from before it when
        // the focus left (=top_t/2 over 0 mm stayed "0 mm").
        if (!f.edit->beingEdited()) f.edit->showValue(f.get(*n));
        // A field an expression drives shows its value, tinted, the expression in its tooltip.
        const auto driven = n->expressions.find(expressionPath(f.key).toStdString());
        const bool isDriven = driven != n->expressions.end();
        f.edit->setProperty("driven", isDriven);
        f.edit->setExpression(isDriven ? QString::fromStdString(driven->second) : QString());
        f.edit->setStyleSheet(isDriven ? QStringLiteral("QAbstractSpinBox { background: #e6efff; }") : QString());
        f.edit->setToolTip(isDriven ? tr("= %1\nDriven by this expression (the Parameters panel); a number typed here "
                                         "replaces it, =... types another.")
                                          .arg(QString::fromStdString(driven->second))
                                    : QString());
    }
    if (profile_ && profileField_ && n->type == shownType_) {
        const auto& pts = profileField_->pointsIn(*n);
        const QSignalBlocker block(profile_);
        profile_->setRowCount(int(pts.size()));
        for (int r = 0; r < int(pts.size()); ++r)
            for (int c = 0; c < 2; ++c) {
                auto* item = new QTableWidgetItem(profileText(pts[std::size_t(r)][c]));
                const std::string path = std::string(profileField_->key) + "[" + std::to_string(r) + "][" +
                                         std::to_string(c) + "]";
                if (const auto e = n->expressions.find(path); e != n->expressions.end()) {
                    // Driven, as a driven field above is shown: the value, tinted,
                    // its expression in the tooltip.
                    item->setData(kExpressionRole, QString::fromStdString(e->second));
                    item->setBackground(QColor(0xe6, 0xef, 0xff));
                    item->setToolTip(tr("= %1\nDriven by this expression (the Parameters panel); a number typed here "
                                        "replaces it, =... types another.")
                                         .arg(QString::fromStdString(e->second)));
                }
                profile_->setItem(r, c, item);
            }
    }
    refreshing_ = false;
}

} // namespace kerf::ui
