"""PDO mapping as a service other capabilities call: read every PDO of a node, recommend and
validate mappings, apply them as one transaction, estimate bus load, decode received PDOs."""
