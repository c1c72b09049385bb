#include "engine/python/ResultArrays.h"

#include <string>

namespace py = pybind11;

namespace skelseg {

py::array_t<std::uint16_t> labelArray(LabelVolume&& labels) {
    const Dims d = labels.dims();
    const py::ssize_t item = sizeof(std::uint16_t);
    return arrayOwning(std::move(labels.values()), {d.x, d.y, d.z},
                       {item, item * d.x, item * d.x * d.y});
}

py::dict skeletonArrays(const SegmentationResult& result) {
    const VolumeGeometry& geometry = result.labels.geometry;
    std::size_t pointCount = 0, edgeCount = 0;
    for (const auto& object : result.objects) {
        pointCount += object.skeleton.size();
        edgeCount += object.skeletonEdges.size();
    }
    std::vector<double> points, rhoC;
    std::vector<std::int32_t> voxels, objectIndex;
    std::vector<std::int64_t> edges;
    std::vector<float> rhoS, sigma;
    std::vector<bool> junctionFlags, criticalFlags;
    points.reserve(3 * pointCount);
    voxels.reserve(3 * pointCount);
    edges.reserve(2 * edgeCount);
    for (std::size_t o = 0; o < result.objects.size(); ++o) {
        const ObjectSegmentation& object = result.objects[o];
        const std::int64_t base = std::int64_t(rhoS.size());
        for (const SkeletonVertex& v : object.skeleton) {
            const auto world = geometry.indexToWorld(v.voxel[0], v.voxel[1], v.voxel[2]);
            points.insert(points.end(), world.begin(), world.end());
            voxels.insert(voxels.end(), v.voxel.begin(), v.voxel.end());
            rhoS.push_back(v.rhoS);
            rhoC.push_back(v.rhoC);
            sigma.push_back(v.sigma);
            junctionFlags.push_back(v.junction);
            criticalFlags.push_back(v.critical);
            objectIndex.push_back(std::int32_t(o));
        }
        for (const auto& e : object.skeletonEdges) {
            edges.push_back(base + e[0]);
            edges.push_back(base + e[1]);
        }
    }
    const auto n = py::ssize_t(pointCount), m = py::ssize_t(edgeCount);
    // std::vector<bool> is packed: numpy needs one byte a flag.
    auto flagArray = [&](const std::vector<bool>& flags) {
        py::array_t<bool> array(n);
        auto view = array.mutable_unchecked<1>();
        for (py::ssize_t i = 0; i < n; ++i) view(i) = flags[std::size_t(i)];
        return array;
    };
    py::dict skeleton;
    skeleton["points"] = arrayOwning(std::move(points), {n, 3});
    skeleton["voxels"] = arrayOwning(std::move(voxels), {n, 3});
    skeleton["edges"] = arrayOwning(std::move(edges), {m, 2});
    skeleton["rho_s"] = arrayOwning(std::move(rhoS), {n});
    skeleton["rho_c"] = arrayOwning(std::move(rhoC), {n});
    skeleton["sigma"] = arrayOwning(std::move(sigma), {n});
    skeleton["junction"] = flagArray(junctionFlags);
    skeleton["critical"] = flagArray(criticalFlags);
    skeleton["object"] = arrayOwning(std::move(objectIndex), {n});
    return skeleton;
}

py::list cutArrays(const SegmentationResult& result) {
    const VolumeGeometry& geometry = result.labels.geometry;
    py::list cuts;
    for (const auto& object : result.objects)
        for (const auto& loop : object.cutLoops) {
            std::vector<double> points;
            points.reserve(3 * loop.size());
            for (const auto& v : loop) {
                const auto world = geometry.indexToWorld(v[0], v[1], v[2]);
                points.insert(points.end(), world.begin(), world.end());
            }
            cuts.append(arrayOwning(std::move(points), {py::ssize_t(loop.size()), 3}));
        }
    return cuts;
}

py::object jsonToPython(const nlohmann::json& value) {
    switch (value.type()) {
        case nlohmann::json::value_t::null:
            return py::none();
        case nlohmann::json::value_t::boolean:
            return py::bool_(value.get<bool>());
        case nlohmann::json::value_t::number_integer:
            return py::int_(value.get<std::int64_t>());
        case nlohmann::json::value_t::number_unsigned:
            return py::int_(value.get<std::uint64_t>());
        case nlohmann::json::value_t::number_float:
            return py::float_(value.get<double>());
        case nlohmann::json::value_t::string:
            return py::str(value.get_ref<const std::string&>());
        case nlohmann::json::value_t::array: {
            py::list list;
            for (const auto& item : value) list.append(jsonToPython(item));
            return std::move(list);
        }
        case nlohmann::json::value_t::object: {
            py::dict dict;
            for (const auto& [key, item] : value.items()) dict[py::str(key)] = jsonToPython(item);
            return std::move(dict);
        }
        default:  // binary, discarded: never in a report
            return py::none();
    }
}

}  // namespace skelseg
