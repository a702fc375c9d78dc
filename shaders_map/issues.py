"""Collects, per material, the nodes that were approximated or are unsupported."""


class Issues:
    def __init__(self):
        self._items = {}  # label -> list of reasons (ordered, unique)

    def add(self, label, reason):
        reasons = self._items.setdefault(label, [])
        if reason not in reasons:
            reasons.append(reason)

    def merge(self, other):
        for label, reasons in other.items():
            for r in reasons:
                self.add(label, r)

    def items(self):
        return list(self._items.items())

    def labels(self):
        return list(self._items)

    def __bool__(self):
        return bool(self._items)

    def __len__(self):
        return len(self._items)

    def format(self, owner_kind, owner_name):
        """One line naming every node: ``Material 'M': Node 'A' (reason); ...``."""
        if not self._items:
            return None
        parts = ["%s (%s)" % (label, ", ".join(reasons)) for label, reasons in self._items.items()]
        return "%s '%s': %s" % (owner_kind, owner_name, "; ".join(parts))
