#include "SelectionGhosts.hpp"

#include "kerf/document/NodePlacement.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshPart.hpp"

#include <QFutureWatcher>
#include <QtConcurrent/QtConcurrentRun>

#include <glm/geometric.hpp>

#include <algorithm>

namespace kerf::ui {

namespace {

constexpr glm::vec3 kGhostColor{0.15f, 0.55f, 1.0f};
constexpr float kGhostOpacity = 0.35f;
// Cells across the smallest primitive of the tool (round enough for a
// ghost), and at most this many across the whole of it (an array of a
// hundred holes stays quick).
constexpr double kCellsAcrossSmallest = 16.0;
constexpr double kCellsAcrossAll = 1500.0;

std::vector<PlacedMesh> meshGhosts(const std::vector<Document>& tools, const Progress& work)
{
    std::vector<PlacedMesh> out;
    for (const Document& doc : tools) {
        const Tape tape = compileTape(doc);
        if (tape.empty() || !tape.bounds().isBounded()) continue;
        double smallest = std::numeric_limits<double>::infinity();
        for (const ShapeInstance& s : tape.shapes()) {
            const glm::dvec3 size = s.worldBounds.size();
            smallest = std::min(smallest, std::max({size.x, size.y, size.z}));
        }
        const glm::dvec3 all = tape.bounds().size();
        MeshOptions options;
        options.featureSize = std::max(smallest / kCellsAcrossSmallest, std::max({all.x, all.y, all.z}) / kCellsAcrossAll);
        options.findHiddenDetail = false;
        const std::optional<Mesh> mesh = meshTape(tape, options, work);
        if (!mesh) return {}; // cancelled
        PlacedMesh ghost;
        ghost.id = "ghost";
        ghost.color = kGhostColor;
        ghost.opacity = kGhostOpacity;
        for (const auto& t : mesh->triangles) {
            const glm::dvec3 a = mesh->vertices[t[0]], b = mesh->vertices[t[1]], c = mesh->vertices[t[2]];
            const glm::dvec3 n = glm::cross(b - a, c - a);
            const double len = glm::length(n);
            const glm::vec3 normal = len > 0.0 ? glm::vec3(n / len) : glm::vec3(0, 0, 1);
            for (const glm::dvec3& v : {a, b, c}) {
                ghost.mesh.positions.push_back(v);
                ghost.mesh.normals.push_back(normal);
                ghost.mesh.bounds = ghost.mesh.bounds.merged(Aabb{v, v});
            }
        }
        out.push_back(std::move(ghost));
    }
    return out;
}

} // namespace

SelectionGhosts::SelectionGhosts(qt::ViewportWidget* viewport, QObject* parent)
    : QObject(parent), viewport_(viewport), generation_(std::make_shared<std::atomic<std::uint64_t>>(0))
{
}

SelectionGhosts::~SelectionGhosts() { ++*generation_; } // whatever still runs stops soon

void SelectionGhosts::show(const Document& doc, const std::vector<std::string>& ids)
{
    std::vector<Document> tools;
    for (const auto& id : ids)
        if (doc.root.find(id) && edit::isSubtracted(doc, id)) tools.push_back(edit::documentOfNodeAlone(doc, id));
    if (tools == shownTools_) return; // shown, or being meshed
    shownTools_ = tools;
    if (!tools.empty() && meshingIds_ == ids) {
        queued_ = std::move(tools); // meshed once the ghosts under way are shown
        return;
    }
    ++*generation_; // what is meshed for another selection is of no use
    queued_.reset();
    meshingIds_.reset();
    if (tools.empty()) {
        if (viewport_->hasGhosts()) viewport_->setGhosts({});
        emit ready();
        return;
    }
    meshingIds_ = ids;
    mesh(std::move(tools));
}

void SelectionGhosts::mesh(std::vector<Document> tools)
{
    const std::uint64_t generation = *generation_;
    ++pending_;
    auto* watcher = new QFutureWatcher<std::vector<PlacedMesh>>(this);
    connect(watcher, &QFutureWatcher<std::vector<PlacedMesh>>::finished, this, [this, watcher, generation] {
        --pending_;
        watcher->deleteLater();
        if (generation != *generation_) return; // a newer selection asked since
        viewport_->setGhosts(watcher->result());
        emit shown();
        if (queued_) {
            std::vector<Document> next = std::move(*queued_);
            queued_.reset();
            mesh(std::move(next));
            return;
        }
        meshingIds_.reset();
        emit ready();
    });
    const auto current = generation_;
    watcher->setFuture(QtConcurrent::run([tools = std::move(tools), current, generation] {
        try {
            return meshGhosts(tools, Progress::cancelledWhen([&] { return current->load() != generation; }));
        } catch (const std::exception&) {
            return std::vector<PlacedMesh>{}; // no ghost is better than a message about one
        }
    }));
}

} // namespace kerf::ui
