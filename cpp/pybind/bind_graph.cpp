// The dataflow engine: Graph, FrameQueue, errors, Python nodes, and one generic binder that
// exposes every registered node kind as mereo.nodes.<kind>(**options).
#include <map>
#include <mutex>

#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "converters.hpp"
#include "errors.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/graph/graph.hpp"
#include "mereo/io/io.hpp"
#include "numpy_view.hpp"

namespace py = pybind11;
using namespace mereo::graph;

namespace mereo::py_util {

namespace {
std::map<std::string, Converter>& converters() {
  static std::map<std::string, Converter> c;
  return c;
}

template <typename T, int C>
Converter image_converter(const char* what) {
  return {[](const Value& v) { return to_numpy(v.get<Image<T, C>>()); },
          [what](const py::handle& h) { return Value::make<Image<T, C>>(from_numpy<T, C>(h, what)); }};
}
}  // namespace

void register_converter(const std::string& type_name, Converter c) { converters()[type_name] = std::move(c); }

py::object value_to_python(const Value& v) {
  if (v.empty()) return py::none();
  auto it = converters().find(v.type().name);
  if (it == converters().end()) return py::str(v.describe());
  return it->second.to_python(v);
}

Value value_from_python(const std::string& type_name, const py::handle& obj) {
  auto it = converters().find(type_name);
  if (it == converters().end()) throw py::type_error("values of port type " + type_name + " cannot come from Python");
  const TypeInfo* t = find_type(type_name);
  return it->second.from_python(obj).as(*t);
}

}  // namespace mereo::py_util

namespace {

using mereo::py_util::value_from_python;
using mereo::py_util::value_to_python;

OptionValue option_from_python(const py::handle& h) {
  if (py::isinstance<py::bool_>(h)) return h.cast<bool>();
  if (py::isinstance<py::int_>(h)) return h.cast<long long>();
  if (py::isinstance<py::float_>(h)) return h.cast<double>();
  if (py::isinstance<py::str>(h)) return h.cast<std::string>();
  throw py::type_error("an option value must be bool, int, float or str, not " +
                       py::str(py::type::of(h)).cast<std::string>());
}

std::map<std::string, OptionValue> options_from_kwargs(const py::dict& kw) {
  std::map<std::string, OptionValue> out;
  for (auto item : kw) out[item.first.cast<std::string>()] = option_from_python(item.second);
  return out;
}

/// mereo.nodes.<kind>(**options): a node to add to a graph.
struct NodeTemplate {
  std::string kind;
  std::map<std::string, OptionValue> options;
};

/// A port of a node in a graph: g.connect(a.out, b.inp) or g.connect("a.out", "b.inp").
struct PortRef {
  std::string node, port;
};

struct NodeRef {
  std::string name, kind;
  std::vector<std::string> inputs, outputs;
};

NodeRef ref_of(const NodeInstance& n) {
  NodeRef r{n.name, n.kind, {}, {}};
  for (const auto& p : n.spec().inputs) r.inputs.push_back(p.name);
  for (const auto& p : n.spec().outputs) r.outputs.push_back(p.name);
  return r;
}

std::string endpoint(const py::handle& h) {
  if (py::isinstance<PortRef>(h)) {
    const auto& p = h.cast<const PortRef&>();
    return p.node + "." + p.port;
  }
  return h.cast<std::string>();
}

std::string spec_doc(const NodeSpec& s) {
  std::string doc = s.doc + "\n\n";
  auto ports = [&](const char* title, const std::vector<PortSpec>& list) {
    if (list.empty()) return;
    doc += std::string(title) + ":\n";
    for (const auto& p : list)
      doc += "    " + p.name + " (" + p.type + (p.required ? "" : ", optional") + "): " + p.doc + "\n";
  };
  ports("Inputs", s.inputs);
  ports("Outputs", s.outputs);
  if (!s.options.empty()) {
    doc += "Options:\n";
    for (const auto& o : s.options) {
      std::string def = std::visit([](const auto& x) {
        std::ostringstream t;
        t << std::boolalpha << x;
        return t.str();
      }, o.default_value);
      doc += "    " + o.name + " (" + to_string(o.type) + ", default " + def;
      if (o.type == OptionType::Int || o.type == OptionType::Double) {
        std::ostringstream r;
        r << ", " << o.min << ".." << o.max;
        doc += r.str();
      }
      if (!o.choices.empty()) {
        doc += ", one of";
        for (const auto& c : o.choices) doc += " " + c;
      }
      doc += "): " + o.doc + "\n";
    }
  }
  return doc;
}

/// A Python callable as a graph-local node (run serially, with the GIL taken). It receives
/// its inputs as keyword arguments and returns its one output, or a dict of outputs.
NodeSpec python_node_spec(py::function fn, const std::vector<std::pair<std::string, std::string>>& inputs,
                          const std::vector<std::pair<std::string, std::string>>& outputs, const std::string& doc) {
  NodeSpec s;
  s.kind = "python:" + py::str(py::getattr(fn, "__name__", py::str("callable"))).cast<std::string>();
  s.doc = doc.empty() ? "A Python callable." : doc;
  for (const auto& [name, type] : inputs) {
    if (!find_type(type)) throw GraphError("python node input '" + name + "': unknown port type '" + type + "'");
    s.inputs.push_back({name, type, "", true});
  }
  for (const auto& [name, type] : outputs) {
    if (!find_type(type)) throw GraphError("python node output '" + name + "': unknown port type '" + type + "'");
    s.outputs.push_back({name, type, "", true});
  }
  if (s.outputs.empty()) throw GraphError("a python node needs at least one output");
  s.serial = true;
  // Shared by the spec's copies; released with the GIL held.
  auto holder = std::shared_ptr<py::function>(new py::function(std::move(fn)), [](py::function* f) {
    py::gil_scoped_acquire gil;
    delete f;
  });
  const auto ins = s.inputs, outs = s.outputs;
  s.make = [holder, ins, outs](const Options&) {
    return NodeBody([holder, ins, outs](NodeContext& ctx) {
      py::gil_scoped_acquire gil;
      try {
        py::dict kw;
        for (const auto& in : ins) kw[py::str(in.name)] = value_to_python(ctx.input_value(in.name));
        py::object result = (*holder)(**kw);
        if (outs.size() == 1 && !py::isinstance<py::dict>(result)) {
          ctx.set_output(outs[0].name, value_from_python(outs[0].type, result));
          return;
        }
        if (!py::isinstance<py::dict>(result))
          throw std::runtime_error("a python node with several outputs must return a dict of them");
        py::dict d = result;
        for (const auto& out : outs) {
          if (!d.contains(out.name)) throw std::runtime_error("the returned dict has no output '" + out.name + "'");
          ctx.set_output(out.name, value_from_python(out.type, d[py::str(out.name)]));
        }
      } catch (py::error_already_set& e) {
        throw std::runtime_error(e.what());
      } catch (const py::cast_error& e) {
        throw std::runtime_error(e.what());
      }
    });
  };
  return s;
}

FrameSource source_from_python(const py::object& src) {
  if (py::isinstance<mereo::io::Sequence>(src)) {
    const auto seq = src.cast<mereo::io::Sequence>();
    return FrameSource::from_function(seq.size(), [seq](std::size_t i) { return seq.load(i); });
  }
  if (py::isinstance<FrameQueue>(src)) return FrameSource::from_queue(src.cast<std::shared_ptr<FrameQueue>>());
  if (py::isinstance<py::str>(src) || py::hasattr(src, "__fspath__")) {
    const auto seq = mereo::io::open({py::str(src).cast<std::string>()});
    return FrameSource::from_function(seq.size(), [seq](std::size_t i) { return seq.load(i); });
  }
  if (py::isinstance<mereo::Frame>(src)) return FrameSource::recorded({src.cast<mereo::Frame>()});
  std::vector<mereo::Frame> frames;
  for (auto item : src) frames.push_back(item.cast<mereo::Frame>());
  return FrameSource::recorded(std::move(frames));
}

py::dict result_to_python(const FrameResult& r) {
  py::dict d;
  d["index"] = r.index;
  d["frame"] = r.frame_id;
  py::dict outs;
  for (const auto& [k, v] : r.outputs) outs[py::str(k)] = value_to_python(v);
  d["outputs"] = outs;
  d["error"] = r.error ? py::object(mereo::py_util::text_to_python(r.error->what())) : py::object(py::none());
  // which node failed and why (the CLI turns a content failure into a warning)
  d["error_node"] = r.error ? py::object(py::str(r.error->node)) : py::object(py::none());
  d["error_cause"] = r.error ? py::object(mereo::py_util::text_to_python(r.error->cause)) : py::object(py::none());
  py::dict times;
  for (const auto& [k, v] : r.timings_ms) times[py::str(k)] = v;
  d["timings_ms"] = times;
  return d;
}

}  // namespace

void bind_graph(py::module_& m) {
  namespace pu = mereo::py_util;
  pu::register_converter("Frame", {[](const Value& v) { return py::cast(v.get<mereo::Frame>()); },
                                   [](const py::handle& h) { return Value::make<mereo::Frame>(h.cast<mereo::Frame>()); }});
  pu::register_converter("Cloud", pu::image_converter<float, 3>("Cloud"));
  pu::register_converter("NormalMap", pu::image_converter<float, 3>("NormalMap"));
  pu::register_converter("Depth", pu::image_converter<float, 1>("Depth"));
  pu::register_converter("Color", pu::image_converter<std::uint8_t, 3>("Color"));
  pu::register_converter("Labels", pu::image_converter<std::uint32_t, 1>("Labels"));
  pu::register_converter("Mask", pu::image_converter<std::uint8_t, 1>("Mask"));
  pu::register_converter("Number", {[](const Value& v) { return py::cast(v.get<double>()); },
                                    [](const py::handle& h) { return Value::make<double>(h.cast<double>()); }});
  pu::register_converter("Text", {[](const Value& v) { return py::cast(v.get<std::string>()); },
                                  [](const py::handle& h) { return Value::make<std::string>(h.cast<std::string>()); }});

  mereo::py_util::register_error<GraphError>(m, "GraphError", PyExc_ValueError);
  mereo::py_util::register_error<NodeError>(m, "NodeError", PyExc_RuntimeError);

  py::class_<PortRef>(m, "Port", "A node's port in a graph: pass it to Graph.connect.")
      .def_readonly("node", &PortRef::node)
      .def_readonly("port", &PortRef::port)
      .def("__repr__", [](const PortRef& p) { return "<mereo.Port " + p.node + "." + p.port + ">"; });

  py::class_<NodeRef>(m, "Node", "A node in a graph; its ports are attributes (node.cloud).")
      .def_readonly("name", &NodeRef::name)
      .def_readonly("kind", &NodeRef::kind)
      .def_readonly("inputs", &NodeRef::inputs)
      .def_readonly("outputs", &NodeRef::outputs)
      .def("__getattr__", [](const NodeRef& n, const std::string& port) {
        for (const auto& list : {n.outputs, n.inputs})
          for (const auto& p : list)
            if (p == port) return PortRef{n.name, port};
        throw py::attribute_error("node '" + n.name + "' (" + n.kind + ") has no port '" + port + "'");
      })
      .def("__repr__", [](const NodeRef& n) { return "<mereo.Node " + n.name + " (" + n.kind + ")>"; });

  py::class_<NodeTemplate>(m, "NodeTemplate", "A node kind with option values, made by mereo.nodes.<kind>(...).")
      .def_readonly("kind", &NodeTemplate::kind)
      .def("__repr__", [](const NodeTemplate& t) { return "<mereo.nodes." + t.kind + ">"; });

  py::class_<FrameQueue, std::shared_ptr<FrameQueue>>(m, "FrameQueue",
      "A live source: push frames from any thread while a graph runs; overflow is 'block', 'drop_oldest' or "
      "'keep_latest'.")
      .def(py::init([](std::size_t capacity, const std::string& overflow) {
             return std::make_shared<FrameQueue>(capacity, overflow_from_string(overflow));
           }),
           py::arg("capacity") = 2, py::arg("overflow") = "block")
      .def("push", [](FrameQueue& q, mereo::Frame frame) { return q.push(std::move(frame)); }, py::arg("frame"),
           py::call_guard<py::gil_scoped_release>())
      .def("close", &FrameQueue::close)
      .def_property_readonly("pushed", &FrameQueue::pushed)
      .def_property_readonly("dropped", &FrameQueue::dropped);

  py::class_<Graph>(m, "Graph",
      "A dataflow graph: add nodes, connect ports, verify, run over frames (deterministic or parallel).")
      .def(py::init<>())
      .def_static("load", [](py::object path) { return Graph::load(py::str(path)); }, py::arg("path"),
                  "Loads a YAML graph file (errors name the file and line).")
      .def_static("parse", &Graph::parse, py::arg("text"), py::arg("file_name") = "<text>")
      .def("add",
           [](Graph& g, py::object what, std::optional<std::string> name, py::kwargs kw) {
             std::string kind;
             std::map<std::string, OptionValue> options;
             if (py::isinstance<NodeTemplate>(what)) {
               const auto& t = what.cast<const NodeTemplate&>();
               kind = t.kind;
               options = t.options;
             } else {
               kind = what.cast<std::string>();
             }
             for (const auto& [k, v] : options_from_kwargs(kw)) options[k] = v;
             return ref_of(g.add(kind, name.value_or(""), options));
           },
           py::arg("kind"), py::arg("name") = py::none(),
           "Adds a node: g.add('estimate_normals', 'normals', window=7) or "
           "g.add(mereo.nodes.estimate_normals(window=7), 'normals').")
      .def("add_python",
           [](Graph& g, py::function fn, const std::string& name,
              const std::vector<std::pair<std::string, std::string>>& inputs,
              const std::vector<std::pair<std::string, std::string>>& outputs, const std::string& doc) {
             return ref_of(g.add_custom(python_node_spec(std::move(fn), inputs, outputs, doc), name));
           },
           py::arg("fn"), py::arg("name"), py::arg("inputs"), py::arg("outputs"), py::arg("doc") = "",
           "Adds a Python callable as a node (for experiments; it runs serially with the GIL). inputs and "
           "outputs are lists of (port, type) pairs; fn gets the inputs as keyword arguments and returns its "
           "output (or a dict of outputs).")
      .def("connect",
           [](Graph& g, py::object from, py::object to) { g.connect(endpoint(from), endpoint(to)); },
           py::arg("source"), py::arg("target"), "Connects an output port to an input port ('a.out' or a.out).")
      .def("node", [](const Graph& g, const std::string& name) { return ref_of(g.node(name)); }, py::arg("name"))
      .def_property_readonly("nodes", [](const Graph& g) {
        std::vector<NodeRef> out;
        for (const auto& n : g.nodes()) out.push_back(ref_of(n));
        return out;
      })
      .def_property_readonly("edges", [](const Graph& g) {
        std::vector<std::pair<std::string, std::string>> out;
        for (const auto& e : g.edges()) out.emplace_back(e.from_node + "." + e.from_port, e.to_node + "." + e.to_port);
        return out;
      })
      .def("set_overflow",
           [](Graph& g, const std::string& policy, std::size_t capacity) {
             g.set_overflow(overflow_from_string(policy), capacity);
           },
           py::arg("policy"), py::arg("capacity") = 2)
      .def("set_options",
           [](Graph& g, const std::string& name, py::kwargs kw) { g.set_options(name, options_from_kwargs(kw)); },
           py::arg("name"), "Changes options of a node: g.set_options('objects', models='mug').")
      .def("verify", &Graph::verify, "Checks ports, types, required inputs, options and cycles.")
      .def("to_yaml", &Graph::to_yaml)
      .def("save", [](const Graph& g, py::object path) { g.save(py::str(path)); }, py::arg("path"))
      .def("to_dot", &Graph::to_dot, "The graph in graphviz's dot language.")
      .def("run",
           [](Graph& g, py::object source, const std::string& mode, std::size_t max_in_flight,
              const std::string& on_error, std::vector<std::string> keep, bool trace, py::object on_result) {
             RunOptions o;
             if (mode == "parallel") o.mode = Mode::Parallel;
             else if (mode != "deterministic")
               throw py::value_error("mode '" + mode + "' is not 'deterministic' or 'parallel'");
             if (on_error == "skip") o.on_error = ErrorPolicy::Skip;
             else if (on_error != "stop") throw py::value_error("on_error '" + on_error + "' is not 'stop' or 'skip'");
             o.max_in_flight = max_in_flight;
             o.keep = std::move(keep);
             o.trace = trace;
             const FrameSource src = source_from_python(source);
             std::vector<FrameResult> results;
             {
               py::gil_scoped_release release;
               g.run(src, o, [&](FrameResult&& r) {
                 if (!on_result.is_none()) {
                   py::gil_scoped_acquire gil;
                   on_result(result_to_python(r));
                 } else {
                   results.push_back(std::move(r));
                 }
               });
             }
             py::list out;
             for (const auto& r : results) out.append(result_to_python(r));
             return out;
           },
           py::arg("source"), py::kw_only(), py::arg("mode") = "deterministic", py::arg("max_in_flight") = 4,
           py::arg("on_error") = "stop", py::arg("keep") = std::vector<std::string>{}, py::arg("trace") = false,
           py::arg("on_result") = py::none(),
           "Runs the graph over a source (a Sequence from mereo.io.open, a path or 'synthetic:N', a list of "
           "Frames, or a FrameQueue). Returns a list of {'index', 'frame', 'outputs', 'error'} in frame order, "
           "or calls on_result(result) for each instead. The GIL is released while it runs.")
      .def("timings", [](const Graph& g) {
        py::list out;
        for (const auto& t : g.last_summary().timings) {
          py::dict d;
          d["node"] = t.node;
          d["count"] = t.count;
          d["mean_ms"] = t.mean_ms;
          d["median_ms"] = t.median_ms;
          d["max_ms"] = t.max_ms;
          d["total_ms"] = t.total_ms;
          out.append(d);
        }
        return out;
      }, "Per-node timing statistics of the last run (count, mean, median, max, total ms).")
      .def("summary", [](const Graph& g) {
        const auto& s = g.last_summary();
        py::dict d;
        d["frames"] = s.frames;
        d["completed"] = s.completed;
        d["failed"] = s.failed;
        d["dropped"] = s.dropped;
        d["wall_ms"] = s.wall_ms;
        return d;
      })
      .def("trace_json", &Graph::trace_json, "The last run's Chrome trace (run with trace=True).")
      .def("write_trace", [](const Graph& g, py::object path) { g.write_trace(py::str(path)); }, py::arg("path"),
           "Writes the Chrome trace (open it in chrome://tracing or Perfetto).")
      .def("_repr_svg_", [](const Graph& g) {
        return py::module_::import("mereo.graph").attr("dot_to_svg")(g.to_dot());
      })
      .def("__repr__", [](const Graph& g) {
        return "<mereo.Graph " + std::to_string(g.nodes().size()) + " nodes, " + std::to_string(g.edges().size()) +
               " edges>";
      });

  // The generic binder: every registered node kind as mereo.nodes.<kind>(**options).
  auto nodes = m.def_submodule("nodes", "Every registered node kind: mereo.nodes.<kind>(**options).");
  py::list kinds;
  for (const auto& spec : node_specs()) {
    const std::string kind = spec.kind;
    nodes.def(
        kind.c_str(),
        [kind](py::kwargs kw) {
          const auto options = options_from_kwargs(kw);
          node_spec(kind).validate(kind, options);  // wrong option names and ranges fail here already
          return NodeTemplate{kind, options};
        },
        spec_doc(spec).c_str());
    kinds.append(kind);
  }
  nodes.attr("__all__") = kinds;
  m.def("node_doc", [](const std::string& kind) { return spec_doc(node_spec(kind)); }, py::arg("kind"),
        "The doc, ports and options of a node kind.");
}
